//! numpy arrays to and from the engine's vectors and index lists, with the checks that
//! turn a wrong shape or index into a `ValueError` naming the array (`tetrasim::mesh::arrays`,
//! which the fuzz target `arrays` runs as well).

use std::borrow::Cow;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use tetrasim::glam::DVec3;
use tetrasim::mesh::arrays;

/// `points` as an `(n, 3)` float64 array.
pub fn points_to_numpy<'py>(py: Python<'py>, points: &[DVec3]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = points.iter().flat_map(|p| p.to_array()).collect();
    Array2::from_shape_vec((points.len(), 3), flat)
        .unwrap_or_else(|_| Array2::zeros((0, 3)))
        .into_pyarray(py)
}

/// `items` (rows of `K` indices) as an `(n, K)` int64 array.
pub fn indices_to_numpy<'py, const K: usize>(
    py: Python<'py>,
    items: &[[u32; K]],
) -> Bound<'py, PyArray2<i64>> {
    let flat: Vec<i64> = items.iter().flatten().map(|&i| i64::from(i)).collect();
    Array2::from_shape_vec((items.len(), K), flat)
        .unwrap_or_else(|_| Array2::zeros((0, K)))
        .into_pyarray(py)
}

/// The values of `array` in row-major order (borrowed where its memory already is) and
/// its shape.
fn row_major<'a, T: numpy::Element + Copy>(
    array: &'a PyReadonlyArray2<'_, T>,
) -> ([usize; 2], Cow<'a, [T]>) {
    let view = array.as_array();
    let shape = [view.shape()[0], view.shape()[1]];
    // ndarray's `to_slice` is `Some` only for memory in standard (row-major) order; a
    // transposed or strided array is copied in that order.
    let values = match view.to_slice() {
        Some(slice) => Cow::Borrowed(slice),
        None => Cow::Owned(view.iter().copied().collect()),
    };
    (shape, values)
}

/// An `(n, 3)` float64 array `what` as points, each finite; `rows` demands that many
/// ([`arrays::points`]).
pub fn points_from_numpy(
    array: &PyReadonlyArray2<'_, f64>,
    what: &str,
    rows: Option<usize>,
) -> PyResult<Vec<DVec3>> {
    let (shape, values) = row_major(array);
    arrays::points(shape, &values, what, rows).map_err(|e| PyValueError::new_err(e.0))
}

/// An `(n, K)` integer array `what` as index rows, each below `bound`
/// ([`arrays::index_rows`]).
pub fn indices_from_numpy<const K: usize>(
    array: &PyReadonlyArray2<'_, i64>,
    what: &str,
    bound: usize,
) -> PyResult<Vec<[u32; K]>> {
    let (shape, values) = row_major(array);
    arrays::index_rows::<K>(shape, &values, what, bound).map_err(|e| PyValueError::new_err(e.0))
}
