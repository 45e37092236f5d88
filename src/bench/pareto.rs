//! Pareto fronts of (cost, error) points: the settings no other setting beats on both.

/// Indices of the points on the Pareto front of `points` = `(cost, error)`, both to be
/// minimised, sorted by increasing cost. A point is on the front when no other point has
/// cost <= and error <= with one of them strictly smaller. Points with a non-finite
/// coordinate are never on it; of exact duplicates, the first is kept.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].0.is_finite() && points[i].1.is_finite())
        .collect();
    // By cost, then error, then index: a point is on the front iff its error is below every
    // error seen before it.
    order.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
            .then(a.cmp(&b))
    });
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for i in order {
        if points[i].1 < best {
            best = points[i].1;
            front.push(i);
        }
    }
    front
}

/// Whether point `a` dominates point `b` (no worse in both, better in one).
pub fn dominates(a: (f64, f64), b: (f64, f64)) -> bool {
    a.0 <= b.0 && a.1 <= b.1 && (a.0 < b.0 || a.1 < b.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_is_non_dominated_and_complete() {
        let pts = [
            (1.0, 10.0),
            (2.0, 5.0),
            (2.0, 6.0),
            (3.0, 5.0),
            (4.0, 1.0),
            (0.5, f64::NAN),
            (5.0, 1.0),
        ];
        let front = pareto_front(&pts);
        assert_eq!(front, vec![0, 1, 4]);
        for (i, &p) in pts.iter().enumerate() {
            if !p.1.is_finite() {
                continue;
            }
            let dominated = pts.iter().any(|&q| q.1.is_finite() && dominates(q, p));
            assert_eq!(front.contains(&i), !dominated, "point {i}");
        }
    }
}
