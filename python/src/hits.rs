//! Query answers as numpy arrays: the [`HitRecord`]s of [`lumis_core::batch::trace_rays`] split
//! into columns, each value the one `lumis hits` writes (float32 bit for bit; ids as int64,
//! exact, where the file's float32 ids are exact up to 2^24).

use lumis_core::batch::{AllHitRecord, HitRecord};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

/// The columns of `records`, built without the GIL: `inst_id` is the instance (Embree's
/// `instID` beside `primID` and `geomID`; -1 outside any instance and for misses), the rest
/// the nine columns of `lumis hits`.
pub struct HitColumns {
    t: Vec<f32>,
    prim_id: Vec<i64>,
    obj_id: Vec<i64>,
    u: Vec<f32>,
    v: Vec<f32>,
    normal: Vec<f32>,
    kind: Vec<i8>,
    inst_id: Vec<i64>,
}

impl HitColumns {
    /// Splits `records` into columns; absent ids and kinds are -1.
    pub fn new(records: &[HitRecord]) -> Self {
        // One parallel pass per column: the split is then a small part of a batch's time on
        // any number of threads (it runs in the query's pool).
        let id = |i: Option<u32>| i.map_or(-1, i64::from);
        let column = |f: &(dyn Fn(&HitRecord) -> f32 + Sync)| records.par_iter().map(f).collect();
        Self {
            t: column(&|r| r.t),
            prim_id: records.par_iter().map(|r| id(r.prim)).collect(),
            obj_id: records.par_iter().map(|r| id(r.object)).collect(),
            u: column(&|r| r.u),
            v: column(&|r| r.v),
            normal: records
                .par_iter()
                .flat_map_iter(|r| r.normal.to_array())
                .collect(),
            kind: records
                .par_iter()
                .map(|r| r.kind.map_or(-1, |k| k as i8))
                .collect(),
            inst_id: records.par_iter().map(|r| id(r.instance)).collect(),
        }
    }

    /// The columns as a dict of numpy arrays (moved, not copied).
    pub fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let n = self.t.len();
        let d = PyDict::new(py);
        d.set_item("t", self.t.into_pyarray(py))?;
        d.set_item("prim_id", self.prim_id.into_pyarray(py))?;
        d.set_item("obj_id", self.obj_id.into_pyarray(py))?;
        d.set_item("u", self.u.into_pyarray(py))?;
        d.set_item("v", self.v.into_pyarray(py))?;
        let normal = Array2::from_shape_vec((n, 3), self.normal).expect("3 floats per record");
        d.set_item("normal", PyArray2::from_owned_array(py, normal))?;
        d.set_item("kind", self.kind.into_pyarray(py))?;
        d.set_item("inst_id", self.inst_id.into_pyarray(py))?;
        Ok(d)
    }
}

/// The columns of all-hits records: `ray` (int64 index), the [`HitColumns`], `graze` (bool).
pub struct AllHitColumns {
    ray: Vec<i64>,
    hits: HitColumns,
    graze: Vec<bool>,
}

impl AllHitColumns {
    /// Splits the records of `parts` (in order, as [`lumis_core::batch::trace_all_hits_parts`]
    /// gives them) into columns, in one pass: each column is allocated once at its final size.
    pub fn new(parts: &[Vec<AllHitRecord>]) -> Self {
        let n = parts.iter().map(Vec::len).sum();
        let mut c = Self {
            ray: Vec::with_capacity(n),
            hits: HitColumns {
                t: Vec::with_capacity(n),
                prim_id: Vec::with_capacity(n),
                obj_id: Vec::with_capacity(n),
                u: Vec::with_capacity(n),
                v: Vec::with_capacity(n),
                normal: Vec::with_capacity(3 * n),
                kind: Vec::with_capacity(n),
                inst_id: Vec::with_capacity(n),
            },
            graze: Vec::with_capacity(n),
        };
        let id = |i: Option<u32>| i.map_or(-1, i64::from);
        for r in parts.iter().flatten() {
            let (h, cols) = (&r.hit, &mut c.hits);
            c.ray.push(r.ray as i64);
            cols.t.push(h.t);
            cols.prim_id.push(id(h.prim));
            cols.obj_id.push(id(h.object));
            cols.u.push(h.u);
            cols.v.push(h.v);
            cols.normal.extend(h.normal.to_array());
            cols.kind.push(h.kind.map_or(-1, |k| k as i8));
            cols.inst_id.push(id(h.instance));
            c.graze.push(r.graze);
        }
        c
    }

    /// The columns as a dict of numpy arrays.
    pub fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let d = self.hits.into_dict(py)?;
        d.set_item("ray", self.ray.into_pyarray(py))?;
        d.set_item("graze", self.graze.into_pyarray(py))?;
        Ok(d)
    }
}

/// Whether each any-hit record found a blocker, as a bool array.
pub fn blocked<'py>(py: Python<'py>, records: &[HitRecord]) -> Bound<'py, PyArray1<bool>> {
    let b: Vec<bool> = records.iter().map(|r| r.t != f32::INFINITY).collect();
    b.into_pyarray(py)
}
