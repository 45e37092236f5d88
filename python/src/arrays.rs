//! numpy arrays to and from the engine's vectors and index lists, with the checks that
//! turn a wrong shape or index into a `ValueError` naming the array.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use tetrasim::glam::DVec3;

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

/// An `(n, 3)` float64 array `what` as points; `rows` demands that many.
pub fn points_from_numpy(
    array: &PyReadonlyArray2<'_, f64>,
    what: &str,
    rows: Option<usize>,
) -> PyResult<Vec<DVec3>> {
    let view = array.as_array();
    let shape = view.shape();
    if shape[1] != 3 || rows.is_some_and(|n| n != shape[0]) {
        let want = rows.map_or("n".to_string(), |n| n.to_string());
        return Err(PyValueError::new_err(format!(
            "`{what}` must have shape ({want}, 3), not {shape:?}"
        )));
    }
    let points: Vec<DVec3> = view
        .rows()
        .into_iter()
        .map(|r| DVec3::new(r[0], r[1], r[2]))
        .collect();
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "`{what}` row {i} is not finite: {:?}",
            points[i]
        )));
    }
    Ok(points)
}

/// An `(n, K)` integer array `what` as index rows, each below `bound`.
pub fn indices_from_numpy<const K: usize>(
    array: &PyReadonlyArray2<'_, i64>,
    what: &str,
    bound: usize,
) -> PyResult<Vec<[u32; K]>> {
    let view = array.as_array();
    let shape = view.shape();
    if shape[1] != K {
        return Err(PyValueError::new_err(format!(
            "`{what}` must have shape (n, {K}), not {shape:?}"
        )));
    }
    let mut out = Vec::with_capacity(shape[0]);
    for (row, values) in view.rows().into_iter().enumerate() {
        let mut item = [0u32; K];
        for (k, &v) in values.iter().enumerate() {
            item[k] = u32::try_from(v)
                .ok()
                .filter(|&i| (i as usize) < bound)
                .ok_or_else(|| {
                    PyValueError::new_err(format!(
                        "`{what}` row {row} holds node {v}, outside 0..{bound}"
                    ))
                })?;
        }
        out.push(item);
    }
    Ok(out)
}
