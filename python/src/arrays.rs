//! Geometry read from numpy arrays, in place (any strides, nothing copied before the checks):
//! vertices `(V, 3)` of float32 or float64, each value rounded to float32 once (to nearest,
//! ties to even, as `astype(numpy.float32)`); faces `(F, 3)` of any integer type; sphere
//! centres `(3,)`; instance matrices `(4, 4)` or `(3, 4)`, row-major. Every refusal is a
//! `ValueError` naming the argument, the row and the value.

use glam::{DAffine3, DMat3, DVec3};
use lumis_core::geometry::Placement;
use lumis_core::math::Vec3;
use lumis_core::scene::limits::MAX_COORDINATE;
use numpy::ndarray::ArrayView2;
use numpy::{Element, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

fn bad(message: String) -> PyErr {
    PyValueError::new_err(message)
}

/// `obj` as a numpy array with `ndim` dimensions, the last of length `width` (when given), or
/// an error naming `what` and the shape expected (`expected`).
fn untyped<'a, 'py>(
    obj: &'a Bound<'py, PyAny>,
    what: &str,
    expected: &str,
    ndim: usize,
    width: Option<usize>,
) -> PyResult<&'a Bound<'py, PyUntypedArray>> {
    let array = obj.cast::<PyUntypedArray>().map_err(|_| {
        bad(format!(
            "{what}: expected a numpy array of shape {expected}"
        ))
    })?;
    let shape = array.shape();
    if shape.len() != ndim || width.is_some_and(|w| shape[ndim - 1] != w) {
        return Err(bad(format!(
            "{what}: shape is {}; expected {expected}",
            shape_text(shape)
        )));
    }
    Ok(array)
}

/// `(2, 3)`, as numpy prints a shape.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The dtype's name (`float16`, `<U1`, `object`).
fn dtype_name(array: &Bound<'_, PyUntypedArray>) -> String {
    let dtype = array.dtype();
    dtype
        .str()
        .map(|s| s.to_string())
        .unwrap_or_else(|_| "unknown".into())
}

/// A float32 or float64 `(N, 3)` view.
enum Floats<'a> {
    F32(ArrayView2<'a, f32>),
    F64(ArrayView2<'a, f64>),
}

impl Floats<'_> {
    fn get(&self, i: usize, k: usize) -> f64 {
        match self {
            Self::F32(a) => a[[i, k]] as f64,
            Self::F64(a) => a[[i, k]],
        }
    }

    /// Value `(i, k)` as given: a float32 with float32's shortest digits.
    fn text(&self, i: usize, k: usize) -> String {
        match self {
            Self::F32(a) => format!("{:?}", a[[i, k]]),
            Self::F64(a) => format!("{:?}", a[[i, k]]),
        }
    }
}

/// `[1.5, NaN, 0.0]`: a row as given (shortest round-trip digits).
fn row_text(row: [f64; 3]) -> String {
    format!("[{:?}, {:?}, {:?}]", row[0], row[1], row[2])
}

/// Vertices `(V, 3)` of float32 or float64, rounded to float32, each finite and within the
/// scene's coordinate limit.
pub fn vertices(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vec3>> {
    rounded_rows(obj, what, "(V, 3)", Some(MAX_COORDINATE))
}

/// Query points `(N, 3)` of float32 or float64, rounded to float32, each finite there (any
/// magnitude: a point beyond the scene's coordinates is simply outside it).
pub fn points(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vec3>> {
    rounded_rows(obj, what, "(N, 3)", None)
}

/// Rows of three float32 or float64 values rounded to float32 once, each finite before and
/// after the rounding, and within `limit` when given.
fn rounded_rows(
    obj: &Bound<'_, PyAny>,
    what: &str,
    shape: &str,
    limit: Option<f32>,
) -> PyResult<Vec<Vec3>> {
    let array = untyped(obj, what, shape, 2, Some(3))?;
    let (f32s, f64s);
    let view = if let Ok(a) = array.extract::<PyReadonlyArray2<'_, f32>>() {
        f32s = a;
        Floats::F32(f32s.as_array())
    } else if let Ok(a) = array.extract::<PyReadonlyArray2<'_, f64>>() {
        f64s = a;
        Floats::F64(f64s.as_array())
    } else {
        return Err(bad(format!(
            "{what}: dtype {} is not float32 or float64",
            dtype_name(array)
        )));
    };
    let n = array.shape()[0];
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let given = [view.get(i, 0), view.get(i, 1), view.get(i, 2)];
        if given.iter().any(|x| !x.is_finite()) {
            let row = (0..3).map(|k| view.text(i, k)).collect::<Vec<_>>();
            return Err(bad(format!(
                "{what} row {i}: [{}] is not finite",
                row.join(", ")
            )));
        }
        let p = Vec3::from_array(given.map(|x| x as f32));
        if let Some(limit) = limit
            && let Some(k) = (0..3).find(|&k| p[k].abs() > limit)
        {
            return Err(bad(format!(
                "{what} row {i}: coordinate {} (float32 {:e}) exceeds the scene's coordinate \
                 limit |x| <= {limit:e}",
                view.text(i, k),
                p[k]
            )));
        }
        if !p.is_finite() {
            let row = (0..3).map(|k| view.text(i, k)).collect::<Vec<_>>();
            return Err(bad(format!(
                "{what} row {i}: [{}] is not finite as float32",
                row.join(", ")
            )));
        }
        out.push(p);
    }
    Ok(out)
}

/// Faces `(F, 3)` of any integer dtype, each index in `0..vertex_count`.
pub fn faces(obj: &Bound<'_, PyAny>, what: &str, vertex_count: usize) -> PyResult<Vec<[u32; 3]>> {
    let array = untyped(obj, what, "(F, 3)", 2, Some(3))?;
    macro_rules! try_dtypes {
        ($($t:ty),*) => {
            $(
                if let Ok(a) = array.extract::<PyReadonlyArray2<'_, $t>>() {
                    return face_rows(a.as_array(), what, vertex_count);
                }
            )*
        };
    }
    try_dtypes!(i64, i32, u32, u64, i16, u16, i8, u8);
    Err(bad(format!(
        "{what}: dtype {} is not an integer type (vertex indices)",
        dtype_name(array)
    )))
}

fn face_rows<T: Element + Copy>(
    a: ArrayView2<'_, T>,
    what: &str,
    vertex_count: usize,
) -> PyResult<Vec<[u32; 3]>>
where
    i128: From<T>,
{
    let mut out = Vec::with_capacity(a.nrows());
    for (i, row) in a.outer_iter().enumerate() {
        let mut face = [0u32; 3];
        for (k, slot) in face.iter_mut().enumerate() {
            let index = i128::from(row[k]);
            if index < 0 {
                return Err(bad(format!(
                    "{what} row {i}: index {index} is negative (vertex indices run from 0 to \
                     V - 1, V = {vertex_count})"
                )));
            }
            if index >= vertex_count as i128 {
                return Err(bad(format!(
                    "{what} row {i}: index {index} is out of range for {vertex_count} vertices"
                )));
            }
            *slot = index as u32;
        }
        out.push(face);
    }
    Ok(out)
}

/// A sphere's centre `(3,)`, rounded to float32 and within the coordinate limit.
pub fn centre(obj: &Bound<'_, PyAny>) -> PyResult<Vec3> {
    let array = untyped(obj, "center", "(3,)", 1, Some(3))?;
    let a = array.extract::<PyReadonlyArray1<'_, f64>>().map_err(|_| {
        bad(format!(
            "center: dtype {} is not float64",
            dtype_name(array)
        ))
    })?;
    let a = a.as_array();
    let given = [a[0], a[1], a[2]];
    if given.iter().any(|x| !x.is_finite()) {
        return Err(bad(format!("center: {} is not finite", row_text(given))));
    }
    let c = Vec3::from_array(given.map(|x| x as f32));
    if c.abs().max_element() > MAX_COORDINATE {
        return Err(bad(format!(
            "center: {} exceeds the scene's coordinate limit |x| <= {MAX_COORDINATE:e}",
            row_text(given)
        )));
    }
    Ok(c)
}

/// A sphere's radius, rounded to float32: finite and > 0.
pub fn radius(r: f64) -> PyResult<f32> {
    let rounded = r as f32;
    if !(rounded.is_finite() && rounded > 0.0) {
        return Err(bad(format!(
            "radius: {r:?} must be finite and > 0 (as float32: {rounded:e})"
        )));
    }
    Ok(rounded)
}

/// An instance matrix, row-major `(4, 4)` (last row `[0, 0, 0, 1]`) or `(3, 4)`, as numpy and
/// trimesh write transforms (`world = M @ [x, y, z, 1]`); refused when it has a non-finite
/// entry or no inverse (the core's [`Placement`] decides and words both).
pub fn placement(obj: &Bound<'_, PyAny>) -> PyResult<DAffine3> {
    let array = untyped(obj, "matrix", "(4, 4) or (3, 4)", 2, Some(4))?;
    let rows = array.shape()[0];
    if rows != 3 && rows != 4 {
        return Err(bad(format!(
            "matrix: shape is {}; expected (4, 4) or (3, 4)",
            shape_text(array.shape())
        )));
    }
    let m = array.extract::<PyReadonlyArray2<'_, f64>>().map_err(|_| {
        bad(format!(
            "matrix: dtype {} is not float64",
            dtype_name(array)
        ))
    })?;
    let m = m.as_array();
    if rows == 4 {
        let last = [m[[3, 0]], m[[3, 1]], m[[3, 2]], m[[3, 3]]];
        if last != [0.0, 0.0, 0.0, 1.0] {
            return Err(bad(format!(
                "matrix: last row is {last:?}; an affine transform's is [0, 0, 0, 1]"
            )));
        }
    }
    let column = |k: usize| DVec3::new(m[[0, k]], m[[1, k]], m[[2, k]]);
    let to_world = DAffine3 {
        matrix3: DMat3::from_cols(column(0), column(1), column(2)),
        translation: column(3),
    };
    Placement::new(to_world).map_err(|e| bad(format!("matrix: {e}")))?;
    Ok(to_world)
}
