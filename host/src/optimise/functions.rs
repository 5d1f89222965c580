//! Standard test functions of global optimisation, with their known minima (Dixon & Szego
//! 1978; Surjanovic & Bingham, "Virtual library of simulation experiments"), for the tests
//! and the benchmark of the optimisers.

use super::Bounds;
use std::f64::consts::PI;

/// Global minimum of [`branin`], attained at `(-pi, 12.275)`, `(pi, 2.275)` and
/// `(9.42478, 2.475)`: `5 / (4 pi)`.
pub const BRANIN_MIN: f64 = 5.0 / (4.0 * PI);

/// Branin-Hoo function on `[-5, 10] x [0, 15]`.
pub fn branin(x: &[f64]) -> f64 {
    let (x1, x2) = (x[0], x[1]);
    let b = 5.1 / (4.0 * PI * PI);
    let c = 5.0 / PI;
    let t = 1.0 / (8.0 * PI);
    (x2 - b * x1 * x1 + c * x1 - 6.0).powi(2) + 10.0 * (1.0 - t) * x1.cos() + 10.0
}

/// The domain of [`branin`].
pub fn branin_bounds() -> Bounds {
    Bounds {
        lower: vec![-5.0, 0.0],
        upper: vec![10.0, 15.0],
    }
}

/// Global minimum of [`hartmann6`] (to the digits published).
pub const HARTMANN6_MIN: f64 = -3.32237;

/// Location of the global minimum of [`hartmann6`].
pub const HARTMANN6_ARGMIN: [f64; 6] = [0.20169, 0.150011, 0.476874, 0.275332, 0.311652, 0.6573];

/// Hartmann 6-D function on `[0, 1]^6` (six local minima).
pub fn hartmann6(x: &[f64]) -> f64 {
    const ALPHA: [f64; 4] = [1.0, 1.2, 3.0, 3.2];
    const A: [[f64; 6]; 4] = [
        [10.0, 3.0, 17.0, 3.5, 1.7, 8.0],
        [0.05, 10.0, 17.0, 0.1, 8.0, 14.0],
        [3.0, 3.5, 1.7, 10.0, 17.0, 8.0],
        [17.0, 8.0, 0.05, 10.0, 0.1, 14.0],
    ];
    const P: [[f64; 6]; 4] = [
        [0.1312, 0.1696, 0.5569, 0.0124, 0.8283, 0.5886],
        [0.2329, 0.4135, 0.8307, 0.3736, 0.1004, 0.9991],
        [0.2348, 0.1451, 0.3522, 0.2883, 0.3047, 0.6650],
        [0.4047, 0.8828, 0.8732, 0.5743, 0.1091, 0.0381],
    ];
    -(0..4)
        .map(|i| {
            let e: f64 = (0..6).map(|j| A[i][j] * (x[j] - P[i][j]).powi(2)).sum();
            ALPHA[i] * (-e).exp()
        })
        .sum::<f64>()
}

/// The domain of [`hartmann6`].
pub fn hartmann6_bounds() -> Bounds {
    Bounds {
        lower: vec![0.0; 6],
        upper: vec![1.0; 6],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn test_functions_have_their_published_minima() {
        // GOAL: the benchmark functions are transcribed correctly.
        // SETUP: evaluate at the published minimisers.
        // REFERENCE: Branin 0.397887 at its three minimisers; Hartmann-6 -3.32237 at
        //            (0.20169, 0.150011, 0.476874, 0.275332, 0.311652, 0.6573).
        for x in [[-PI, 12.275], [PI, 2.275], [9.42478, 2.475]] {
            assert!(
                (branin(&x) - 0.397887).abs() < 1e-5,
                "{x:?}: {}",
                branin(&x)
            );
        }
        assert!((BRANIN_MIN - 0.397887).abs() < 1e-6);
        let h = hartmann6(&HARTMANN6_ARGMIN);
        assert!((h - HARTMANN6_MIN).abs() < 1e-5, "{h}");
    }
}
