//! The exact solution of the Riemann problem for the ideal gas (Toro, *Riemann Solvers and
//! Numerical Methods for Fluid Dynamics*, 3rd ed. 2009, ch. 4): the star pressure by Newton
//! iteration on the pressure function (eqs. 4.5-4.9) from the two-rarefaction guess
//! (eq. 4.46), the star velocity (eq. 4.9), and the sampled solution (sec. 4.5).

/// A gas state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GasState {
    /// Density (kg/m^3).
    pub density: f64,
    /// Velocity (m/s).
    pub velocity: f64,
    /// Pressure (Pa).
    pub pressure: f64,
}

/// Why a Riemann problem has no solution here.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum RiemannError {
    /// A density or pressure is not positive, or gamma is not above 1.
    #[error("Riemann problem: invalid {0}")]
    Invalid(&'static str),
    /// The data generate a vacuum (Toro eq. 4.40), which this solver does not treat.
    #[error("Riemann problem: the data generate a vacuum")]
    Vacuum,
    /// Newton's iteration did not converge.
    #[error("Riemann problem: the star pressure did not converge")]
    NoConvergence,
}

/// The solved problem: the states on both sides and the star region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RiemannSolution {
    /// Left state.
    pub left: GasState,
    /// Right state.
    pub right: GasState,
    /// Ratio of specific heats.
    pub gamma: f64,
    /// Star pressure `p*`.
    pub star_pressure: f64,
    /// Star velocity `u*`.
    pub star_velocity: f64,
}

fn sound(state: &GasState, gamma: f64) -> f64 {
    libm::sqrt(gamma * state.pressure / state.density)
}

/// Toro's `f_K(p)` and its derivative (eqs. 4.6-4.7, 4.37).
fn side_function(p: f64, state: &GasState, gamma: f64) -> (f64, f64) {
    let c = sound(state, gamma);
    if p > state.pressure {
        let a = 2.0 / ((gamma + 1.0) * state.density);
        let b = (gamma - 1.0) / (gamma + 1.0) * state.pressure;
        let root = libm::sqrt(a / (p + b));
        (
            (p - state.pressure) * root,
            root * (1.0 - 0.5 * (p - state.pressure) / (b + p)),
        )
    } else {
        let ratio = p / state.pressure;
        let exponent = (gamma - 1.0) / (2.0 * gamma);
        (
            2.0 * c / (gamma - 1.0) * (libm::pow(ratio, exponent) - 1.0),
            libm::pow(ratio, -(gamma + 1.0) / (2.0 * gamma)) / (state.density * c),
        )
    }
}

/// Solve the Riemann problem `left | right` of an ideal gas with ratio `gamma`.
pub fn solve(left: GasState, right: GasState, gamma: f64) -> Result<RiemannSolution, RiemannError> {
    if gamma.is_nan() || gamma <= 1.0 {
        return Err(RiemannError::Invalid("gamma"));
    }
    for (state, name) in [(&left, "left state"), (&right, "right state")] {
        let ok = state.density > 0.0
            && state.pressure > 0.0
            && state.velocity.is_finite()
            && state.density.is_finite()
            && state.pressure.is_finite();
        if !ok {
            return Err(RiemannError::Invalid(name));
        }
    }
    let (cl, cr) = (sound(&left, gamma), sound(&right, gamma));
    // Pressure positivity condition (Toro eq. 4.40).
    if 2.0 * (cl + cr) / (gamma - 1.0) <= right.velocity - left.velocity {
        return Err(RiemannError::Vacuum);
    }
    let z = (gamma - 1.0) / (2.0 * gamma);
    let du = right.velocity - left.velocity;
    // Two-rarefaction guess (Toro eq. 4.46).
    let mut p = libm::pow(
        (cl + cr - 0.5 * (gamma - 1.0) * du)
            / (cl / libm::pow(left.pressure, z) + cr / libm::pow(right.pressure, z)),
        1.0 / z,
    )
    .max(1e-12 * left.pressure.min(right.pressure));
    for _ in 0..100 {
        let (fl, dl) = side_function(p, &left, gamma);
        let (fr, dr) = side_function(p, &right, gamma);
        let next = (p - (fl + fr + du) / (dl + dr)).max(1e-14 * p);
        let change = 2.0 * (next - p).abs() / (next + p);
        p = next;
        if change < 1e-14 {
            let (fl, _) = side_function(p, &left, gamma);
            let (fr, _) = side_function(p, &right, gamma);
            return Ok(RiemannSolution {
                left,
                right,
                gamma,
                star_pressure: p,
                star_velocity: 0.5 * (left.velocity + right.velocity) + 0.5 * (fr - fl),
            });
        }
    }
    Err(RiemannError::NoConvergence)
}

impl RiemannSolution {
    /// The state at `x/t = speed` (Toro sec. 4.5, Fig. 4.14).
    pub fn sample(&self, speed: f64) -> GasState {
        let g = self.gamma;
        let (ps, us) = (self.star_pressure, self.star_velocity);
        // Mirror the right side onto the left: u -> -u.
        let (state, s, sign) = if speed <= us {
            (self.left, speed, 1.0)
        } else {
            let r = self.right;
            (
                GasState {
                    velocity: -r.velocity,
                    ..r
                },
                -speed,
                -1.0,
            )
        };
        let us = sign * us;
        let c = sound(&state, g);
        let result = if ps > state.pressure {
            // Shock (Toro eqs. 4.50, 4.52).
            let ratio = ps / state.pressure;
            let shock = state.velocity
                - c * libm::sqrt((g + 1.0) / (2.0 * g) * ratio + (g - 1.0) / (2.0 * g));
            if s <= shock {
                state
            } else {
                let gr = (g - 1.0) / (g + 1.0);
                GasState {
                    density: state.density * (ratio + gr) / (gr * ratio + 1.0),
                    velocity: us,
                    pressure: ps,
                }
            }
        } else {
            // Rarefaction (Toro eqs. 4.53-4.56).
            let head = state.velocity - c;
            let star_density = state.density * libm::pow(ps / state.pressure, 1.0 / g);
            let tail = us - c * libm::pow(ps / state.pressure, (g - 1.0) / (2.0 * g));
            if s <= head {
                state
            } else if s >= tail {
                GasState {
                    density: star_density,
                    velocity: us,
                    pressure: ps,
                }
            } else {
                let factor = 2.0 / (g + 1.0) + (g - 1.0) / ((g + 1.0) * c) * (state.velocity - s);
                GasState {
                    density: state.density * libm::pow(factor, 2.0 / (g - 1.0)),
                    velocity: 2.0 / (g + 1.0) * (c + 0.5 * (g - 1.0) * state.velocity + s),
                    pressure: state.pressure * libm::pow(factor, 2.0 * g / (g - 1.0)),
                }
            }
        };
        GasState {
            velocity: sign * result.velocity,
            ..result
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(density: f64, velocity: f64, pressure: f64) -> GasState {
        GasState {
            density,
            velocity,
            pressure,
        }
    }

    /// GOAL: the star states of Toro's five test problems.
    /// SETUP: gamma 1.4; Toro Table 4.1 data.
    /// REFERENCE: Toro (2009) Table 4.3 (p*, u*), to the printed digits.
    #[test]
    fn toro_star_states() {
        let cases = [
            (
                state(1.0, 0.0, 1.0),
                state(0.125, 0.0, 0.1),
                0.30313,
                0.92745,
            ),
            (state(1.0, -2.0, 0.4), state(1.0, 2.0, 0.4), 0.00189, 0.0),
            (
                state(1.0, 0.0, 1000.0),
                state(1.0, 0.0, 0.01),
                460.894,
                19.5975,
            ),
            (
                state(1.0, 0.0, 0.01),
                state(1.0, 0.0, 100.0),
                46.0950,
                -6.19633,
            ),
            (
                state(5.99924, 19.5975, 460.894),
                state(5.99242, -6.19633, 46.0950),
                1691.64,
                8.68975,
            ),
        ];
        for (k, (left, right, p, u)) in cases.into_iter().enumerate() {
            let solution = solve(left, right, 1.4).unwrap();
            let dp = (solution.star_pressure - p).abs();
            let du = (solution.star_velocity - u).abs();
            assert!(
                dp < 0.5e-5 * p.max(1.0) + 1e-5,
                "test {}: p* {}",
                k + 1,
                solution.star_pressure
            );
            assert!(
                du < 1e-5 * u.abs().max(1.0),
                "test {}: u* {}",
                k + 1,
                solution.star_velocity
            );
        }
    }

    /// GOAL: the sampled Sod solution has the textbook plateaus and shock speed.
    /// SETUP: Sod (Toro test 1), x/t in the star regions and across the shock.
    /// REFERENCE: Toro (2009) sec. 4.3.3: rho*L 0.42632, rho*R 0.26557; shock speed 1.75216.
    #[test]
    fn sod_plateaus_and_shock() {
        let sod = solve(state(1.0, 0.0, 1.0), state(0.125, 0.0, 0.1), 1.4).unwrap();
        assert!((sod.sample(0.5).density - 0.42632).abs() < 1e-5);
        assert!((sod.sample(1.5).density - 0.26557).abs() < 1e-5);
        assert!((sod.sample(1.7521).density - 0.26557).abs() < 1e-5);
        assert!((sod.sample(1.7522).density - 0.125).abs() < 1e-12);
        assert_eq!(sod.sample(-2.0), state(1.0, 0.0, 1.0));
    }

    /// GOAL: bad data and vacuum generation give typed errors.
    #[test]
    fn bad_data_and_vacuum_are_refused() {
        let good = state(1.0, 0.0, 1.0);
        assert_eq!(
            solve(state(-1.0, 0.0, 1.0), good, 1.4),
            Err(RiemannError::Invalid("left state"))
        );
        assert_eq!(solve(good, good, 1.0), Err(RiemannError::Invalid("gamma")));
        assert_eq!(
            solve(state(1.0, -20.0, 0.4), state(1.0, 20.0, 0.4), 1.4),
            Err(RiemannError::Vacuum)
        );
    }
}
