//! Row-major arrays (numpy's, as the Python layer hands them over) as points and index
//! rows, with the checks that turn a wrong shape, an index out of range or a value that is
//! not finite into an error naming the array, its row and the value. Plain slices in and
//! out, so the fuzz target `arrays` runs the same checks as `tetrasim.Mesh(nodes, tets)`.

use glam::DVec3;

/// What an array fails with: a message naming the array (a `ValueError` in Python).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ArrayError(pub String);

impl std::fmt::Display for ArrayError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ArrayError {}

/// Checks that `values` fill `shape` and that it has `columns` columns (and `rows` rows,
/// when given).
fn check_shape<T>(
    shape: [usize; 2],
    values: &[T],
    what: &str,
    rows: Option<usize>,
    columns: usize,
) -> Result<(), ArrayError> {
    let want = rows.map_or("n".to_string(), |n| n.to_string());
    if shape[1] != columns || rows.is_some_and(|n| n != shape[0]) {
        return Err(ArrayError(format!(
            "`{what}` must have shape ({want}, {columns}), not {shape:?}"
        )));
    }
    if shape[0].checked_mul(shape[1]) != Some(values.len()) {
        return Err(ArrayError(format!(
            "`{what}` of shape {shape:?} holds {} values",
            values.len()
        )));
    }
    Ok(())
}

/// An `(n, 3)` array `what` of `values` (row-major) as points, each finite; `rows`
/// demands that many.
pub fn points(
    shape: [usize; 2],
    values: &[f64],
    what: &str,
    rows: Option<usize>,
) -> Result<Vec<DVec3>, ArrayError> {
    check_shape(shape, values, what, rows, 3)?;
    let points: Vec<DVec3> = values
        .chunks_exact(3)
        .map(|r| DVec3::new(r[0], r[1], r[2]))
        .collect();
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(ArrayError(format!(
            "`{what}` row {i} is not finite: {:?}",
            points[i]
        )));
    }
    Ok(points)
}

/// An `(n, K)` integer array `what` of `values` (row-major) as index rows, each index in
/// `0..bound`.
pub fn index_rows<const K: usize>(
    shape: [usize; 2],
    values: &[i64],
    what: &str,
    bound: usize,
) -> Result<Vec<[u32; K]>, ArrayError> {
    check_shape(shape, values, what, None, K)?;
    values
        .chunks_exact(K)
        .enumerate()
        .map(|(row, values)| {
            let mut item = [0u32; K];
            for (slot, &v) in item.iter_mut().zip(values) {
                *slot = u32::try_from(v)
                    .ok()
                    .filter(|&i| (i as usize) < bound)
                    .ok_or_else(|| {
                        ArrayError(format!(
                            "`{what}` row {row} holds node {v}, outside 0..{bound}"
                        ))
                    })?;
            }
            Ok(item)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_come_in_rows_of_three_and_finite() {
        let p = points([2, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0], "nodes", None).unwrap();
        assert_eq!(
            p,
            vec![DVec3::new(0.0, 1.0, 2.0), DVec3::new(3.0, 4.0, 5.0)]
        );
        let err = points([1, 2], &[0.0, 1.0], "nodes", None).unwrap_err();
        assert_eq!(err.0, "`nodes` must have shape (n, 3), not [1, 2]");
        let err = points([1, 3], &[0.0; 3], "positions", Some(4)).unwrap_err();
        assert_eq!(err.0, "`positions` must have shape (4, 3), not [1, 3]");
        let err = points([2, 3], &[0.0, 0.0, 0.0, 1.0, f64::NAN, 0.0], "v", None).unwrap_err();
        assert!(err.0.starts_with("`v` row 1 is not finite"), "{err}");
        let err = points([2, 3], &[0.0; 3], "v", None).unwrap_err();
        assert_eq!(err.0, "`v` of shape [2, 3] holds 3 values");
    }

    #[test]
    fn indices_are_refused_outside_the_nodes() {
        let t = index_rows::<4>([1, 4], &[0, 1, 2, 3], "tets", 4).unwrap();
        assert_eq!(t, vec![[0, 1, 2, 3]]);
        for bad in [4, -1, i64::MAX] {
            let err = index_rows::<4>([1, 4], &[0, 1, 2, bad], "tets", 4).unwrap_err();
            assert_eq!(
                err.0,
                format!("`tets` row 0 holds node {bad}, outside 0..4")
            );
        }
        let err = index_rows::<4>([1, 3], &[0, 1, 2], "tets", 4).unwrap_err();
        assert_eq!(err.0, "`tets` must have shape (n, 4), not [1, 3]");
    }
}
