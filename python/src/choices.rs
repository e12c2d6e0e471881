//! The keyword arguments that name a library choice (`accel=`, `precision=`, `up=`,
//! `layout=`, `tonemap=`, `display=`, `aovs=`): parsed by the library types' own `FromStr`,
//! the names `lumis render` takes, with the messages saying which keyword was wrong and
//! listing the names it takes.

use std::str::FromStr;

use lumis_core::accel::AccelKind;
use lumis_core::film::{DisplayTransform, Tonemap};
use lumis_core::geometry::Precision;
use lumis_core::scene::UpAxis;
use lumis_io::output::ChannelLayout;
use lumis_io::request::Aov;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// `"a", "b" or "c"`.
fn alternatives(names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    match quoted.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// `value` as the library parses it, or `{what}={value:?}: expected {expected}`.
fn parse<T: FromStr>(what: &str, value: &str, expected: impl FnOnce() -> String) -> PyResult<T> {
    value
        .parse()
        .map_err(|_| PyValueError::new_err(format!("{what}={value:?}: expected {}", expected())))
}

/// `accel=`: the `--accel` values (the default first).
pub fn accel(s: &str) -> PyResult<AccelKind> {
    use AccelKind::*;
    parse("accel", s, || {
        alternatives(&[Sah, Brute, Bsp, Bsmp].map(AccelKind::name))
    })
}

/// `precision=`: the `--precision` values (the default first).
pub fn precision(s: &str) -> PyResult<Precision> {
    use Precision::*;
    parse("precision", s, || {
        alternatives(&[Watertight, Fast, Double].map(Precision::name))
    })
}

/// `up=`: the `--up` values, in either case; `None` is the default, y.
pub fn up(s: Option<&str>) -> PyResult<UpAxis> {
    let Some(s) = s else {
        return Ok(UpAxis::default());
    };
    s.to_ascii_lowercase().parse().map_err(|_| {
        PyValueError::new_err(format!(
            "up={s:?}: expected {}",
            alternatives(&UpAxis::ALL.map(UpAxis::name))
        ))
    })
}

/// `layout=`: the `--layout` values.
pub fn layout(s: &str) -> PyResult<ChannelLayout> {
    parse("layout", s, || {
        one_of(&ChannelLayout::ALL.map(ChannelLayout::name))
    })
}

/// `tonemap=`: the `--tonemap` values.
pub fn tonemap(s: &str) -> PyResult<Tonemap> {
    parse("tonemap", s, || one_of(&Tonemap::ALL.map(Tonemap::name)))
}

/// `display=`: the `--display` values; `None` keeps the scene's.
pub fn display(s: Option<&str>) -> PyResult<Option<DisplayTransform>> {
    s.map(|s| {
        parse("display", s, || {
            one_of(&DisplayTransform::ALL.map(DisplayTransform::name))
        })
    })
    .transpose()
}

/// `aovs=`: the `--aov` values.
pub fn aovs(names: &[String]) -> PyResult<Vec<Aov>> {
    names
        .iter()
        .map(|a| {
            a.parse().map_err(|_| {
                PyValueError::new_err(format!(
                    "aovs: {a:?} is not a layer; expected {}",
                    alternatives(&Aov::ALL.map(Aov::name))
                ))
            })
        })
        .collect()
}

/// `one of ["a", "b"]`.
fn one_of(names: &[&str]) -> String {
    format!("one of {names:?}")
}

/// Every name each keyword takes, from the library types (`lumis._lumis.CHOICES`): what the
/// package's `Literal` types must list (python/tests/test_typing.py checks them).
pub fn names(py: Python<'_>) -> PyResult<Bound<'_, pyo3::types::PyDict>> {
    let d = pyo3::types::PyDict::new(py);
    d.set_item("accel", AccelKind::ALL.map(AccelKind::name))?;
    d.set_item("precision", Precision::ALL.map(Precision::name))?;
    d.set_item("up", UpAxis::ALL.map(UpAxis::name))?;
    d.set_item("layout", ChannelLayout::ALL.map(ChannelLayout::name))?;
    d.set_item("tonemap", Tonemap::ALL.map(Tonemap::name))?;
    d.set_item("display", DisplayTransform::ALL.map(DisplayTransform::name))?;
    d.set_item("aov", Aov::ALL.map(Aov::name))?;
    Ok(d)
}
