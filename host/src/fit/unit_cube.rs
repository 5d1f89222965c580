//! The one map between a bounded constant and its unit coordinate: `lower..upper` onto
//! `0..1` and back. The optimisers, the Nelder-Mead polish and the least-squares refits all
//! work in these coordinates; each caller decides whether to clamp.

/// `value` in unit coordinates of `[lower, upper]`: `(value - lower) / (upper - lower)`.
pub fn to_unit(value: f64, lower: f64, upper: f64) -> f64 {
    (value - lower) / (upper - lower)
}

/// Unit coordinate `unit` of `[lower, upper]` in physical units: `lower + unit (upper - lower)`.
pub fn from_unit(unit: f64, lower: f64, upper: f64) -> f64 {
    lower + unit * (upper - lower)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_takes_the_bounds_to_zero_and_one_and_back() {
        // GOAL: the bounds map onto the unit interval's ends; a round trip returns the value.
        // SETUP: bounds [-5, 3e9]. REFERENCE: 0 and 1 exactly; round trip within 1 ulp-scale.
        assert_eq!(to_unit(-5.0, -5.0, 3e9), 0.0);
        assert_eq!(to_unit(3e9, -5.0, 3e9), 1.0);
        assert_eq!(from_unit(0.0, -5.0, 3e9), -5.0);
        assert_eq!(from_unit(1.0, -5.0, 3e9), 3e9);
        let x = 1.234e8;
        assert!((from_unit(to_unit(x, -5.0, 3e9), -5.0, 3e9) - x).abs() < 1e-6);
    }
}
