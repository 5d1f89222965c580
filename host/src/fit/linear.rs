//! Small dense least squares for the refits: column-major products, the damped Cholesky
//! solve, the residual-maker projection and the dot product. Pure arithmetic in a fixed
//! order (`libm::sqrt`), so results are the same on every platform.

/// A column-major dense matrix: `columns[j][i]` is row `i` of column `j`.
pub type Columns = [Vec<f64>];

/// `A' b` for the columns `A`.
pub fn transpose_times(a: &Columns, b: &[f64]) -> Vec<f64> {
    a.iter()
        .map(|column| column.iter().zip(b).map(|(x, y)| x * y).sum())
        .collect()
}

/// `A' A` for the columns `A` (row-major `p x p`).
pub fn gram(a: &Columns) -> Vec<Vec<f64>> {
    a.iter()
        .map(|ci| {
            a.iter()
                .map(|cj| ci.iter().zip(cj).map(|(x, y)| x * y).sum())
                .collect()
        })
        .collect()
}

/// Solve the symmetric positive (semi-)definite system `(G + ridge diag(G)) x = b` by
/// Cholesky, with a floor on the diagonal (`1e-12` of the largest) so that a direction the
/// data do not determine gets a zero step rather than an infinite one. `None` if the matrix
/// is not positive definite even then.
pub fn solve_damped(matrix: &[Vec<f64>], rhs: &[f64], ridge: f64) -> Option<Vec<f64>> {
    let n = rhs.len();
    let largest = (0..n).map(|i| matrix[i][i]).fold(0.0, f64::max);
    let floor = 1e-12 * largest.max(f64::MIN_POSITIVE);
    let mut l = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in 0..=i {
            let mut sum = matrix[i][j];
            if i == j {
                sum += ridge * matrix[i][i] + floor;
            }
            sum -= l[i][..j]
                .iter()
                .zip(&l[j][..j])
                .map(|(a, b)| a * b)
                .sum::<f64>();
            if i == j {
                if sum <= 0.0 || !sum.is_finite() {
                    return None;
                }
                l[i][i] = libm::sqrt(sum);
            } else {
                l[i][j] = sum / l[j][j];
            }
        }
    }
    let mut y = vec![0.0; n];
    for i in 0..n {
        let s: f64 = (0..i).map(|k| l[i][k] * y[k]).sum();
        y[i] = (rhs[i] - s) / l[i][i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|k| l[k][i] * x[k]).sum();
        x[i] = (y[i] - s) / l[i][i];
    }
    Some(x)
}

/// `v - A (A'A)^-1 A' v`: the part of `v` that re-tuning the columns `A` cannot reproduce
/// (the residual-maker `M` of least squares applied to `v`).
pub fn project_out(a: &Columns, v: &[f64]) -> Vec<f64> {
    if a.is_empty() {
        return v.to_vec();
    }
    let coefficients =
        solve_damped(&gram(a), &transpose_times(a, v), 0.0).unwrap_or_else(|| vec![0.0; a.len()]);
    let mut out = v.to_vec();
    for (column, c) in a.iter().zip(&coefficients) {
        for (o, x) in out.iter_mut().zip(column) {
            *o -= c * x;
        }
    }
    out
}

/// Dot product.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_removes_what_the_columns_explain() {
        // GOAL: the residual-maker of the score test. SETUP: columns (1,1,1,1) and (0,1,2,3);
        // v = 2 + 3 t + (1,-1,-1,1). REFERENCE: M v = (1,-1,-1,1) (orthogonal to both columns).
        let columns = vec![vec![1.0; 4], vec![0.0, 1.0, 2.0, 3.0]];
        let bump = [1.0, -1.0, -1.0, 1.0];
        let v: Vec<f64> = (0..4).map(|i| 2.0 + 3.0 * i as f64 + bump[i]).collect();
        let projected = project_out(&columns, &v);
        for (p, b) in projected.iter().zip(bump) {
            assert!((p - b).abs() < 1e-9, "{projected:?}");
        }
    }
}
