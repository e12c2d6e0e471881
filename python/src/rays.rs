//! Rays read in place from numpy arrays: origins and directions `(N, 3)` of float32 or float64
//! (any strides, nothing copied), `t_min` and `t_max` scalars or `(N,)` arrays. Each value
//! is rounded to float32 once, as `array.astype(numpy.float32)` does (round to nearest even),
//! which is what `lumis hits` reads from its float32 `.npy` rows.

use lumis_core::batch::RayBatch;
use lumis_core::math::{Ray, Vec3};
use numpy::ndarray::{ArrayView1, ArrayView2};
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// A borrowed `(N, 3)` array.
pub enum Points<'py> {
    F32(PyReadonlyArray2<'py, f32>),
    F64(PyReadonlyArray2<'py, f64>),
}

/// A borrowed `t_min` or `t_max`: one value for every ray, or one per ray.
pub enum Bound1<'py> {
    Scalar(f32),
    F32(PyReadonlyArray1<'py, f32>),
    F64(PyReadonlyArray1<'py, f64>),
}

impl<'py> Points<'py> {
    /// `obj` as an `(N, 3)` float32 or float64 array, or a `TypeError`/`ValueError` naming
    /// `what`.
    pub fn extract(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Self> {
        let points = if let Ok(a) = obj.extract::<PyReadonlyArray2<'py, f32>>() {
            Self::F32(a)
        } else if let Ok(a) = obj.extract::<PyReadonlyArray2<'py, f64>>() {
            Self::F64(a)
        } else {
            return Err(PyTypeError::new_err(format!(
                "{what}: expected a 2-D numpy array of float32 or float64, shape (N, 3)"
            )));
        };
        let shape = match &points {
            Self::F32(a) => a.shape().to_vec(),
            Self::F64(a) => a.shape().to_vec(),
        };
        if shape[1] != 3 {
            return Err(PyValueError::new_err(format!(
                "{what}: shape is {shape:?}; expected (N, 3)"
            )));
        }
        Ok(points)
    }

    fn len(&self) -> usize {
        match self {
            Self::F32(a) => a.shape()[0],
            Self::F64(a) => a.shape()[0],
        }
    }

    fn view(&self) -> PointsView<'_> {
        match self {
            Self::F32(a) => PointsView::F32(a.as_array()),
            Self::F64(a) => PointsView::F64(a.as_array()),
        }
    }
}

impl<'py> Bound1<'py> {
    /// `obj` as a number or an `(n,)` float32/float64 array, or an error naming `what`.
    pub fn extract(obj: &Bound<'py, PyAny>, what: &str, n: usize) -> PyResult<Self> {
        let bound = if let Ok(a) = obj.extract::<PyReadonlyArray1<'py, f32>>() {
            Self::F32(a)
        } else if let Ok(a) = obj.extract::<PyReadonlyArray1<'py, f64>>() {
            Self::F64(a)
        } else if let Ok(x) = obj.extract::<f64>() {
            Self::Scalar(x as f32)
        } else {
            return Err(PyTypeError::new_err(format!(
                "{what}: expected a number or a 1-D numpy array of float32 or float64, shape (N,)"
            )));
        };
        let len = match &bound {
            Self::Scalar(_) => n,
            Self::F32(a) => a.len(),
            Self::F64(a) => a.len(),
        };
        if len != n {
            return Err(PyValueError::new_err(format!(
                "{what}: {len} values for {n} rays"
            )));
        }
        Ok(bound)
    }

    fn view(&self) -> BoundView<'_> {
        match self {
            Self::Scalar(x) => BoundView::Scalar(*x),
            Self::F32(a) => BoundView::F32(a.as_array()),
            Self::F64(a) => BoundView::F64(a.as_array()),
        }
    }
}

enum PointsView<'a> {
    F32(ArrayView2<'a, f32>),
    F64(ArrayView2<'a, f64>),
}

enum BoundView<'a> {
    Scalar(f32),
    F32(ArrayView1<'a, f32>),
    F64(ArrayView1<'a, f64>),
}

impl PointsView<'_> {
    #[inline]
    fn get(&self, i: usize) -> Vec3 {
        match self {
            Self::F32(a) => Vec3::new(a[[i, 0]], a[[i, 1]], a[[i, 2]]),
            Self::F64(a) => Vec3::new(a[[i, 0]] as f32, a[[i, 1]] as f32, a[[i, 2]] as f32),
        }
    }
}

impl BoundView<'_> {
    #[inline]
    fn get(&self, i: usize) -> f32 {
        match self {
            Self::Scalar(x) => *x,
            Self::F32(a) => a[i],
            Self::F64(a) => a[i] as f32,
        }
    }
}

/// The borrowed arrays of one query, read without the GIL (the borrows stay held by the
/// caller, so numpy's borrow checking keeps Rust writers out meanwhile).
pub struct NumpyRays<'a> {
    origins: PointsView<'a>,
    directions: PointsView<'a>,
    t_min: BoundView<'a>,
    t_max: BoundView<'a>,
    len: usize,
}

/// The arguments of one query, extracted and checked for shape.
pub struct RayArgs<'py> {
    origins: Points<'py>,
    directions: Points<'py>,
    t_min: Bound1<'py>,
    t_max: Bound1<'py>,
}

impl<'py> RayArgs<'py> {
    /// Extracts the four arguments; origins and directions must have the same length.
    pub fn extract(
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        t_min: &Bound<'py, PyAny>,
        t_max: &Bound<'py, PyAny>,
    ) -> PyResult<Self> {
        let origins = Points::extract(origins, "origins")?;
        let directions = Points::extract(directions, "directions")?;
        let n = origins.len();
        if directions.len() != n {
            return Err(PyValueError::new_err(format!(
                "{n} origins but {} directions",
                directions.len()
            )));
        }
        Ok(Self {
            t_min: Bound1::extract(t_min, "t_min", n)?,
            t_max: Bound1::extract(t_max, "t_max", n)?,
            origins,
            directions,
        })
    }

    /// The rays, viewed in place.
    pub fn rays(&self) -> NumpyRays<'_> {
        NumpyRays {
            origins: self.origins.view(),
            directions: self.directions.view(),
            t_min: self.t_min.view(),
            t_max: self.t_max.view(),
            len: self.origins.len(),
        }
    }
}

impl RayBatch for NumpyRays<'_> {
    fn len(&self) -> usize {
        self.len
    }

    #[inline]
    fn ray(&self, i: usize) -> Ray {
        Ray {
            origin: self.origins.get(i),
            dir: self.directions.get(i),
            t_min: self.t_min.get(i),
            t_max: self.t_max.get(i),
        }
    }
}
