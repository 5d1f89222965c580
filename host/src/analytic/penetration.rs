//! Long-rod penetration into a semi-infinite target: the Tate–Alekseevskii modified Bernoulli
//! model and the Walker–Anderson time-dependent model, integrated in time.
//!
//! Notation (SI units throughout): the rod has density ρp, strength (flow stress) Yp = σp,
//! current length L, rear (undeformed part) velocity v; its nose moves into the target at the
//! penetration velocity u and is at the depth P; the target has density ρt, the Tate resistance
//! Rt, the flow stress σt, the bulk modulus K and the shear modulus G.
//!
//! Both models are integrated with the classical fourth-order Runge–Kutta scheme at a fixed
//! internal step of at most [`INTERNAL_STEP`] (1 ns), aligned with the output times. Near the
//! end of a model's validity (rod consumed, rod or nose stopped) the step is halved until the
//! end is resolved to [`MIN_STEP_FRACTION`] of the step; the history then ends there.
//!
//! Sources: Tate, J. Mech. Phys. Solids 15 (1967) 387 and 17 (1969) 141; Alekseevskii, Combust.
//! Explos. Shock Waves 2 (1966) 63; in the form of Segletes & Walters, Int. J. Impact Eng. 28
//! (2003) 363. Walker & Anderson, Int. J. Impact Eng. 16 (1995) 19–48, with the implementation
//! choices (Hugoniot start, crater radius fit) of the public C# code `awcsc` (`CalcAW`).

/// Fixed internal time step of the Runge–Kutta integrations (s).
pub const INTERNAL_STEP: f64 = 1.0e-9;

/// Smallest fraction of the internal step tried (by halving) before the end of a model's
/// validity is declared reached.
pub const MIN_STEP_FRACTION: f64 = 1.0e-6;

/// Largest number of output samples a history may ask for.
const MAX_SAMPLES: f64 = 1.0e7;

/// Rod erosion fractions (L0 − L)/L0 bounding the quasi-steady window.
pub const QUASI_STEADY_EROSION_WINDOW: (f64, f64) = (0.3, 0.7);

/// Linear shock Hugoniot (Us = C + S·up) used for tungsten heavy alloy: C (m/s), S; Steinberg's
/// values for tungsten (UCRL-MA-106439, 1996).
pub const TUNGSTEN_ALLOY_HUGONIOT: (f64, f64) = (4029.0, 1.237);

/// Linear shock Hugoniot (Us = C + S·up) of steel: C (m/s), S; Steinberg's values for 4340
/// steel (UCRL-MA-106439, 1996).
pub const STEEL_HUGONIOT: (f64, f64) = (4570.0, 1.49);

/// Why a penetration model could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AnalyticError {
    /// An input is NaN or infinite.
    #[error("{quantity} must be finite, got {value}")]
    NonFinite {
        /// Which input.
        quantity: &'static str,
        /// Its value.
        value: f64,
    },
    /// An input that must be strictly positive is not.
    #[error("{quantity} must be positive, got {value}")]
    NotPositive {
        /// Which input.
        quantity: &'static str,
        /// Its value.
        value: f64,
    },
    /// An input that must be non-negative is negative.
    #[error("{quantity} must not be negative, got {value}")]
    Negative {
        /// Which input.
        quantity: &'static str,
        /// Its value.
        value: f64,
    },
    /// The inputs are valid numbers but outside the range where the model is defined.
    #[error("outside the model's range: {0}")]
    OutsideModel(String),
    /// A history is too short for the requested measure.
    #[error("history too short: {0}")]
    HistoryTooShort(String),
}

fn finite(quantity: &'static str, value: f64) -> Result<f64, AnalyticError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(AnalyticError::NonFinite { quantity, value })
    }
}

fn positive(quantity: &'static str, value: f64) -> Result<f64, AnalyticError> {
    if finite(quantity, value)? > 0.0 {
        Ok(value)
    } else {
        Err(AnalyticError::NotPositive { quantity, value })
    }
}

fn non_negative(quantity: &'static str, value: f64) -> Result<f64, AnalyticError> {
    if finite(quantity, value)? >= 0.0 {
        Ok(value)
    } else {
        Err(AnalyticError::Negative { quantity, value })
    }
}

/// A rod striking a semi-infinite target normally. Each model reads only the fields it needs
/// (listed per field); the others may hold anything.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodTarget {
    /// Rod density ρp (kg/m³). Tate, Walker–Anderson.
    pub rod_density: f64,
    /// Rod strength (Pa): Tate's Yp, Walker–Anderson's flow stress σp. Both.
    pub rod_strength: f64,
    /// Initial rod length L0 (m). Both.
    pub rod_length: f64,
    /// Rod diameter (m). Walker–Anderson (default crater radius).
    pub rod_diameter: f64,
    /// Wave speed c of the rod's deceleration term, the elastic bar speed √(E/ρp) in
    /// Walker–Anderson (m/s). Walker–Anderson.
    pub rod_bar_wave_speed: f64,
    /// Rod shock Hugoniot (C in m/s, S) for the impact pressure match. Walker–Anderson.
    pub rod_hugoniot: (f64, f64),
    /// Target density ρt (kg/m³). Both.
    pub target_density: f64,
    /// Target flow stress σt (Pa). Walker–Anderson.
    pub target_strength: f64,
    /// Tate's target resistance Rt (Pa). Tate.
    pub target_resistance: f64,
    /// Target bulk modulus K (Pa). Walker–Anderson.
    pub target_bulk_modulus: f64,
    /// Target shear modulus G (Pa). Walker–Anderson.
    pub target_shear_modulus: f64,
    /// Target shock Hugoniot (C in m/s, S). Walker–Anderson.
    pub target_hugoniot: (f64, f64),
    /// Striking velocity V0 (m/s). Both.
    pub striking_velocity: f64,
}

/// The state of a penetration at one time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PenetrationSample {
    /// Time since impact (s).
    pub time: f64,
    /// Depth of the rod nose below the original target surface, P (m).
    pub nose_depth: f64,
    /// Current rod length L (m).
    pub rod_length: f64,
    /// Velocity of the rod's rear, v (m/s).
    pub rod_velocity: f64,
    /// Penetration (nose) velocity u (m/s).
    pub penetration_velocity: f64,
}

/// Nose depth at `time` by linear interpolation of a history: the first depth before the
/// history starts, the last after it ends (the models stop when penetration has ended). NaN for
/// an empty history or a NaN time.
pub fn depth_at(history: &[PenetrationSample], time: f64) -> f64 {
    let (Some(first), Some(last)) = (history.first(), history.last()) else {
        return f64::NAN;
    };
    if time.is_nan() {
        return f64::NAN;
    }
    if time <= first.time {
        return first.nose_depth;
    }
    if time >= last.time {
        return last.nose_depth;
    }
    // First sample at or after `time`; it exists and has an index >= 1 here.
    let after = history.partition_point(|sample| sample.time < time);
    let (a, b) = (&history[after - 1], &history[after]);
    let span = b.time - a.time;
    if span <= 0.0 {
        return b.nose_depth;
    }
    a.nose_depth + (b.nose_depth - a.nose_depth) * (time - a.time) / span
}

/// Mean penetration velocity over the quasi-steady phase, defined as the window in which the rod
/// has eroded from 30 % to 70 % of its initial length ([`QUASI_STEADY_EROSION_WINDOW`]):
/// ΔP/Δt between the two crossing times, each found by linear interpolation of the history.
/// The initial length is that of the first sample.
pub fn quasi_steady_penetration_velocity(
    history: &[PenetrationSample],
) -> Result<f64, AnalyticError> {
    let (start, end) = quasi_steady_window(history)?;
    Ok((end.nose_depth - start.nose_depth) / (end.time - start.time))
}

/// The interpolated samples where the rod length first falls to 70 % and 30 % of the initial.
fn quasi_steady_window(
    history: &[PenetrationSample],
) -> Result<(PenetrationSample, PenetrationSample), AnalyticError> {
    let first = history
        .first()
        .ok_or_else(|| AnalyticError::HistoryTooShort("the history is empty".into()))?;
    let initial_length = first.rod_length;
    let crossing = |fraction_eroded: f64| {
        let length = initial_length * (1.0 - fraction_eroded);
        let index = history.iter().position(|s| s.rod_length <= length)?;
        if index == 0 {
            return None;
        }
        let (a, b) = (&history[index - 1], &history[index]);
        let w = (a.rod_length - length) / (a.rod_length - b.rod_length);
        let mix = |x: f64, y: f64| x + (y - x) * w;
        Some(PenetrationSample {
            time: mix(a.time, b.time),
            nose_depth: mix(a.nose_depth, b.nose_depth),
            rod_length: length,
            rod_velocity: mix(a.rod_velocity, b.rod_velocity),
            penetration_velocity: mix(a.penetration_velocity, b.penetration_velocity),
        })
    };
    let (low, high) = QUASI_STEADY_EROSION_WINDOW;
    match (crossing(low), crossing(high)) {
        (Some(start), Some(end)) if end.time > start.time => Ok((start, end)),
        _ => Err(AnalyticError::HistoryTooShort(format!(
            "the rod does not erode from {:.0} % to {:.0} % of its length within the history",
            100.0 * low,
            100.0 * high
        ))),
    }
}

// ------------------------------------------------------------------------------------------
// Time integration shared by both models.

/// Integrates y' = rhs(y) from t = 0 to `end_time` with classical RK4 at steps of at most
/// `max_step`, recording a sample every `output_interval` (and at `end_time`). `rhs` returns
/// None for a state outside the model's domain; a step whose stages or result leave the domain
/// is halved, down to [`MIN_STEP_FRACTION`] of the step, after which the history ends with the
/// last admissible state.
fn integrate<const N: usize>(
    initial: [f64; N],
    rhs: impl Fn(&[f64; N]) -> Option<[f64; N]>,
    to_sample: impl Fn(f64, &[f64; N]) -> PenetrationSample,
    end_time: f64,
    output_interval: f64,
    max_step: f64,
) -> Result<Vec<PenetrationSample>, AnalyticError> {
    positive("end time", end_time)?;
    positive("output interval", output_interval)?;
    let intervals = (end_time / output_interval * (1.0 - 1e-12)).ceil().max(1.0);
    if intervals > MAX_SAMPLES {
        return Err(AnalyticError::OutsideModel(format!(
            "{intervals:.0} output samples asked for (at most {MAX_SAMPLES:.0})"
        )));
    }
    let intervals = intervals as usize;
    let mut y = initial;
    let mut dy = rhs(&y).ok_or_else(|| {
        AnalyticError::OutsideModel("the model is undefined at the moment of impact".into())
    })?;
    let mut t = 0.0;
    let mut samples = Vec::with_capacity(intervals + 1);
    samples.push(to_sample(0.0, &y));
    for k in 1..=intervals {
        let t_output = if k == intervals {
            end_time
        } else {
            k as f64 * output_interval
        };
        let t_start = t;
        let substeps = ((t_output - t_start) / max_step).ceil().max(1.0);
        let h_nominal = (t_output - t_start) / substeps;
        let h_min = h_nominal * MIN_STEP_FRACTION;
        let substeps = substeps as usize;
        let mut h = h_nominal;
        for j in 1..=substeps {
            let t_to = if j == substeps {
                t_output
            } else {
                t_start + j as f64 * h_nominal
            };
            while t < t_to {
                let step = h.min(t_to - t);
                match rk4_step(&y, &dy, step, &rhs) {
                    Some((y_next, dy_next)) => {
                        y = y_next;
                        dy = dy_next;
                        t = if t_to - (t + step) <= 1e-9 * h_nominal {
                            t_to
                        } else {
                            t + step
                        };
                        h = (2.0 * step).min(h_nominal);
                    }
                    None => {
                        h = 0.5 * step;
                        if h < h_min {
                            samples.push(to_sample(t, &y));
                            return Ok(samples);
                        }
                    }
                }
            }
        }
        samples.push(to_sample(t_output, &y));
    }
    Ok(samples)
}

/// One classical Runge–Kutta step from (y, y'), returning the new state and its derivative, or
/// None when a stage or the result is outside the model's domain or not finite.
fn rk4_step<const N: usize>(
    y: &[f64; N],
    k1: &[f64; N],
    h: f64,
    rhs: &impl Fn(&[f64; N]) -> Option<[f64; N]>,
) -> Option<([f64; N], [f64; N])> {
    let along = |k: &[f64; N], factor: f64| {
        let mut out = *y;
        for (o, d) in out.iter_mut().zip(k) {
            *o += factor * d;
        }
        out
    };
    let k2 = rhs(&along(k1, 0.5 * h))?;
    let k3 = rhs(&along(&k2, 0.5 * h))?;
    let k4 = rhs(&along(&k3, h))?;
    let mut next = *y;
    for i in 0..N {
        next[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
    if next.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let derivative = rhs(&next)?;
    Some((next, derivative))
}

// ------------------------------------------------------------------------------------------
// Tate–Alekseevskii.

/// Depth-to-length ratio of hydrodynamic penetration, P/L = √(ρp/ρt) (Birkhoff et al. 1948;
/// the strengthless limit of Tate's model).
pub fn hydrodynamic_depth_ratio(
    rod_density: f64,
    target_density: f64,
) -> Result<f64, AnalyticError> {
    let rod_density = positive("rod density", rod_density)?;
    let target_density = positive("target density", target_density)?;
    Ok((rod_density / target_density).sqrt())
}

/// Tate's target resistance estimated from the target's flow stress and Young's modulus:
/// Rt ≈ σt (2/3 + ln(0.57 Et/σt)) (Tate, Int. J. Mech. Sci. 28 (1986) 599, from the quasi-static
/// spherical cavity expansion).
pub fn tate_resistance_estimate(
    target_strength: f64,
    target_youngs_modulus: f64,
) -> Result<f64, AnalyticError> {
    let strength = positive("target strength", target_strength)?;
    let modulus = positive("target Young's modulus", target_youngs_modulus)?;
    if modulus <= strength {
        return Err(AnalyticError::OutsideModel(format!(
            "Young's modulus {modulus:.3e} Pa not above the strength {strength:.3e} Pa"
        )));
    }
    Ok(strength * (2.0 / 3.0 + libm::log(0.57 * modulus / strength)))
}

/// The Tate–Alekseevskii inputs, validated.
#[derive(Debug, Clone, Copy)]
struct Tate {
    rod_density: f64,
    rod_strength: f64,
    target_density: f64,
    target_resistance: f64,
}

impl Tate {
    fn new(case: &RodTarget) -> Result<Self, AnalyticError> {
        Ok(Tate {
            rod_density: positive("rod density", case.rod_density)?,
            rod_strength: non_negative("rod strength", case.rod_strength)?,
            target_density: positive("target density", case.target_density)?,
            target_resistance: non_negative("target resistance", case.target_resistance)?,
        })
    }

    /// Penetration velocity u for the rod velocity v ≥ 0 from the modified Bernoulli equation
    /// ½ρp(v−u)² + Yp = ½ρt u² + Rt, restricted to 0 ≤ u ≤ v:
    /// - u = 0 when even u = 0 leaves the rod pressure ½ρp v² + Yp at or below Rt (the rod
    ///   erodes without penetrating);
    /// - u = v when even u = v leaves the target pressure ½ρt v² + Rt at or below Yp (the rod
    ///   penetrates rigidly);
    /// - otherwise the root in (0, v), from the quadratic a u² + b u + c = 0 with
    ///   a = ½(ρt−ρp), b = ρp v, c = −(½ρp v² + Yp − Rt), written u = −2c/(b + √(b² − 4ac)),
    ///   which has no cancellation and covers ρp = ρt (u = −c/b).
    fn penetration_velocity(&self, v: f64) -> f64 {
        let (rp, rt) = (self.rod_density, self.target_density);
        let strength_difference = self.rod_strength - self.target_resistance;
        let rod_pressure_at_rest = 0.5 * rp * v * v + strength_difference;
        if rod_pressure_at_rest <= 0.0 {
            return 0.0;
        }
        if strength_difference >= 0.5 * rt * v * v {
            return v;
        }
        let a = 0.5 * (rt - rp);
        let b = rp * v;
        let c = -rod_pressure_at_rest;
        let discriminant = (b * b - 4.0 * a * c).max(0.0);
        (-2.0 * c / (b + discriminant.sqrt())).clamp(0.0, v)
    }

    /// Right-hand side of Tate's equations for the state (v, L, P):
    /// eroding (u < v): L v̇ = −Yp/ρp, L̇ = −(v−u), Ṗ = u;
    /// rigid (u = v): ρp L v̇ = −(Rt + ½ρt v²), L̇ = 0, Ṗ = v (the target's resistance decelerates
    /// the whole rod; it equals −Yp/(ρp L) at the onset, so v̇ is continuous).
    /// Outside the domain (v < 0 or L ≤ 0): None.
    fn rhs(&self, state: &[f64; 3]) -> Option<[f64; 3]> {
        let [v, length, _depth] = *state;
        if !(v >= 0.0 && length > 0.0) {
            return None;
        }
        let u = self.penetration_velocity(v);
        if u >= v && v > 0.0 {
            let resistance = self.target_resistance + 0.5 * self.target_density * v * v;
            Some([-resistance / (self.rod_density * length), 0.0, v])
        } else if v == 0.0 {
            // The rod has stopped: nothing moves any more.
            Some([0.0, 0.0, 0.0])
        } else {
            Some([
                -self.rod_strength / (self.rod_density * length),
                -(v - u),
                u,
            ])
        }
    }
}

/// Steady penetration velocity u of Tate's model for the rod velocity v (the modified Bernoulli
/// equation ½ρp(v−u)² + Yp = ½ρt u² + Rt; u = 0 when the rod cannot overcome Rt, u = v when
/// the rod is too strong to erode; see the regimes of [`tate_history`]).
pub fn tate_steady_penetration_velocity(
    case: &RodTarget,
    rod_velocity: f64,
) -> Result<f64, AnalyticError> {
    let tate = Tate::new(case)?;
    let v = non_negative("rod velocity", rod_velocity)?;
    Ok(tate.penetration_velocity(v))
}

/// History of the Tate–Alekseevskii model (Segletes & Walters 2003, eqs 1–4):
/// L v̇ = −Yp/ρp; ½ρp(v−u)² + Yp = ½ρt u² + Rt; L̇ = −(v−u); Ṗ = u, from v = V0, L = L0, P = 0.
///
/// Regimes: while ½ρp v² + Yp ≤ Rt the rod erodes at the rate v without penetrating (u = 0);
/// while Yp ≥ Rt + ½ρt v² it penetrates rigidly (u = v, L constant) and decelerates as
/// ρp L v̇ = −(Rt + ½ρt v²). The history ends at `end_time`, when the rod is consumed
/// (L → 0) or when it stops (v → 0); samples every `output_interval` and at the end.
/// Integration: RK4 at 1 ns ([`INTERNAL_STEP`]).
pub fn tate_history(
    case: &RodTarget,
    end_time: f64,
    output_interval: f64,
) -> Result<Vec<PenetrationSample>, AnalyticError> {
    let tate = Tate::new(case)?;
    let length = positive("rod length", case.rod_length)?;
    let velocity = positive("striking velocity", case.striking_velocity)?;
    integrate(
        [velocity, length, 0.0],
        |state| tate.rhs(state),
        |time, &[v, length, depth]| PenetrationSample {
            time,
            nose_depth: depth,
            rod_length: length,
            rod_velocity: v,
            penetration_velocity: tate.penetration_velocity(v),
        },
        end_time,
        output_interval,
        INTERNAL_STEP,
    )
}

// ------------------------------------------------------------------------------------------
// Cavity expansion.

/// Hill's quasi-static pressure to expand a spherical cavity from zero radius in an
/// elastic-perfectly plastic solid, `sigma_s = 2/3 Y [1 + ln(E / (3 (1 - nu) Y))]` (Hill, The
/// Mathematical Theory of Plasticity, 1950; Forrestal's static term), with `E` and `nu` from
/// the bulk and shear moduli (Pa).
pub fn spherical_cavity_pressure(yield_stress: f64, bulk_modulus: f64, shear_modulus: f64) -> f64 {
    let young = 9.0 * bulk_modulus * shear_modulus / (3.0 * bulk_modulus + shear_modulus);
    let poisson =
        (3.0 * bulk_modulus - 2.0 * shear_modulus) / (2.0 * (3.0 * bulk_modulus + shear_modulus));
    2.0 / 3.0 * yield_stress * (1.0 + libm::log(young / (3.0 * (1.0 - poisson) * yield_stress)))
}

/// The inertial coefficient `B` of the dynamic spherical cavity expansion of an incompressible
/// elastic-plastic target, `sigma_r = sigma_s + B rho_t V^2` (Forrestal & Luk, J. Appl. Mech.
/// 55 (1988) 275-279). A compressible target's is somewhat smaller.
pub const INCOMPRESSIBLE_INERTIAL_COEFFICIENT: f64 = 1.5;

/// Nose shape factor `N` of a tangent-ogive nose of caliber-radius-head `psi` on a rigid
/// projectile in a spherical-cavity-expansion target, `N = (8 psi - 1) / (24 psi^2)`
/// (Forrestal, Okajima & Luk, J. Appl. Mech. 55 (1988) 755-760; frictionless): the axial
/// force is `pi a^2 (sigma_s + N B rho_t V^2)`. At `psi = 1/2` the ogive is the hemisphere,
/// `N = 1/2`; a flat nose has `N = 1`.
pub fn ogive_nose_factor(caliber_radius_head: f64) -> f64 {
    let psi = caliber_radius_head;
    (8.0 * psi - 1.0) / (24.0 * psi * psi)
}

/// A rigid projectile striking a semi-infinite target normally.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidProjectile {
    /// Projectile mass `m` (kg).
    pub mass: f64,
    /// Shank radius `a` (m).
    pub radius: f64,
    /// Nose shape factor `N` ([`ogive_nose_factor`]).
    pub nose_factor: f64,
    /// Target density `rho_t` (kg/m³).
    pub target_density: f64,
    /// The target's quasi-static cavity pressure `sigma_s` (Pa), e.g.
    /// [`spherical_cavity_pressure`].
    pub static_resistance: f64,
    /// The inertial coefficient `B` ([`INCOMPRESSIBLE_INERTIAL_COEFFICIENT`]).
    pub inertial_coefficient: f64,
    /// Striking velocity `V0` (m/s).
    pub striking_velocity: f64,
}

impl RigidProjectile {
    /// The final depth, `m / (2 pi a^2 N B rho_t) ln(1 + N B rho_t V0^2 / sigma_s)` (the
    /// closed form of [`rigid_projectile_history`]'s equation of motion).
    pub fn final_depth(&self) -> Result<f64, AnalyticError> {
        let (area, inertial) = self.checked()?;
        let v0 = self.striking_velocity;
        Ok(self.mass / (2.0 * area * inertial)
            * libm::log1p(inertial * v0 * v0 / self.static_resistance))
    }

    /// `(pi a^2, N B rho_t)`, the inputs validated.
    fn checked(&self) -> Result<(f64, f64), AnalyticError> {
        positive("projectile mass", self.mass)?;
        let radius = positive("projectile radius", self.radius)?;
        let n = positive("nose factor", self.nose_factor)?;
        let rho = positive("target density", self.target_density)?;
        positive("static resistance", self.static_resistance)?;
        let b = non_negative("inertial coefficient", self.inertial_coefficient)?;
        non_negative("striking velocity", self.striking_velocity)?;
        if b == 0.0 {
            return Err(AnalyticError::OutsideModel(
                "an inertial coefficient of zero has no logarithmic depth".into(),
            ));
        }
        Ok((core::f64::consts::PI * radius * radius, n * b * rho))
    }
}

/// History of a rigid projectile's penetration by the cavity-expansion force (Forrestal &
/// Luk 1988; Forrestal, Okajima & Luk 1988): `m dV/dt = -pi a^2 (sigma_s + N B rho_t V^2)`,
/// `dP/dt = V`, from `V0` at the first contact to rest. **Simplified:** the whole nose resists
/// from the first contact (no nose-entry phase, no cratering at the front face), no friction,
/// the target semi-infinite. Samples every `output_interval` and at the end (`end_time` or
/// rest); RK4 at 1 ns ([`INTERNAL_STEP`]). `rod_length` is left at zero and
/// `penetration_velocity` is the projectile's.
pub fn rigid_projectile_history(
    projectile: &RigidProjectile,
    end_time: f64,
    output_interval: f64,
) -> Result<Vec<PenetrationSample>, AnalyticError> {
    let (area, inertial) = projectile.checked()?;
    let (mass, resistance) = (projectile.mass, projectile.static_resistance);
    integrate(
        [projectile.striking_velocity, 0.0],
        |&[v, _]| (v >= 0.0).then(|| [-area * (resistance + inertial * v * v) / mass, v]),
        |time, &[v, depth]| PenetrationSample {
            time,
            nose_depth: depth,
            rod_length: 0.0,
            rod_velocity: v,
            penetration_velocity: v,
        },
        end_time,
        output_interval,
        INTERNAL_STEP,
    )
}

// ------------------------------------------------------------------------------------------
// Walker–Anderson.

/// Crater radius of the `awcsc` code's `CalcAW` default: R = Rp (1 + 2.87e-4 V0 + 1.48e-7 V0²)
/// with the rod radius Rp (m) and the striking velocity V0 in m/s.
pub fn default_crater_radius(
    rod_diameter: f64,
    striking_velocity: f64,
) -> Result<f64, AnalyticError> {
    let diameter = positive("rod diameter", rod_diameter)?;
    let v0 = non_negative("striking velocity", striking_velocity)?;
    Ok(0.5 * diameter * (1.0 + 2.87e-4 * v0 + 1.48e-7 * v0 * v0))
}

/// Interface (particle) velocity u0 just after impact from the shock Hugoniots of rod and
/// target, Us = C + S up: ρp (Cp + Sp (V0−u))(V0−u) = ρt (Ct + St u) u (the start of
/// Walker–Anderson, as in `awcsc`). Solved by bisection on [0, V0], where the difference of the
/// two pressures decreases from positive to negative.
pub fn hugoniot_interface_velocity(case: &RodTarget) -> Result<f64, AnalyticError> {
    let rp = positive("rod density", case.rod_density)?;
    let rt = positive("target density", case.target_density)?;
    let (cp, sp) = case.rod_hugoniot;
    let (ct, st) = case.target_hugoniot;
    positive("rod Hugoniot C", cp)?;
    non_negative("rod Hugoniot S", sp)?;
    positive("target Hugoniot C", ct)?;
    non_negative("target Hugoniot S", st)?;
    let v0 = positive("striking velocity", case.striking_velocity)?;
    let pressure_difference = |u: f64| {
        let w = v0 - u;
        rp * (cp + sp * w) * w - rt * (ct + st * u) * u
    };
    let (mut low, mut high) = (0.0, v0);
    for _ in 0..200 {
        let mid = 0.5 * (low + high);
        if mid <= low || mid >= high {
            break;
        }
        if pressure_difference(mid) > 0.0 {
            low = mid;
        } else {
            high = mid;
        }
    }
    Ok(0.5 * (low + high))
}

/// The target's inputs to Walker–Anderson's cavity expansion, validated.
#[derive(Debug, Clone, Copy)]
struct TargetCavity {
    density: f64,
    strength: f64,
    bulk_modulus: f64,
    shear_modulus: f64,
}

/// The Walker–Anderson inputs, validated.
#[derive(Debug, Clone, Copy)]
struct WalkerAnderson {
    rod_density: f64,
    rod_strength: f64,
    rod_wave_speed: f64,
    target: TargetCavity,
    crater_radius: f64,
}

/// The target's plastic zone at one penetration velocity: α and dα/du.
#[derive(Debug, Clone, Copy)]
struct PlasticZone {
    alpha: f64,
    alpha_rate: f64,
}

impl TargetCavity {
    fn new(case: &RodTarget) -> Result<Self, AnalyticError> {
        let target = TargetCavity {
            density: positive("target density", case.target_density)?,
            strength: positive("target strength", case.target_strength)?,
            bulk_modulus: positive("target bulk modulus", case.target_bulk_modulus)?,
            shear_modulus: positive("target shear modulus", case.target_shear_modulus)?,
        };
        if target.strength >= 2.0 * target.shear_modulus {
            return Err(AnalyticError::OutsideModel(format!(
                "target strength {:.3e} Pa must be below twice the shear modulus for a plastic \
                 zone to exist",
                target.strength
            )));
        }
        Ok(target)
    }

    /// Extent α ≥ 1 of the target's plastic zone in crater radii, from Walker–Anderson's dynamic
    /// cavity expansion (1 + ρt u²/σt)² (K − ρt α² u²) = (1 + ρt α² u²/(2G))² (K − ρt u²), and
    /// its derivative dα/du.
    ///
    /// With q = ρt u² and x = α² the equation is the quadratic C D² x² + (2CD + B) x + C − A = 0
    /// with A = (1 + q/σt)² K, B = (1 + q/σt)² q, C = K − q, D = q/(2G); for σt < 2G and q < K
    /// it has exactly one root in (1, K/q), taken as x = 2(A−C)/[(2CD+B) + √((2CD+B)² +
    /// 4CD²(A−C))] with A − C = K a(2+a) + q, a = q/σt (no cancellation). As u → 0 the
    /// equation linearises to x = (1 + 2K/σt)/(1 + K/G) (→ 2G/σt for an incompressible
    /// target, the quasi-static cavity expansion). dα/du follows from implicit
    /// differentiation: dx/dq = −Φ_q/Φ_x, dα/du = dx/dq · ρt u/α.
    /// None when q ≥ K (the penetration outruns the target's bulk wave speed).
    fn plastic_zone(&self, u: f64) -> Option<PlasticZone> {
        let (k, g, sigma) = (self.bulk_modulus, self.shear_modulus, self.strength);
        let q = self.density * u * u;
        if q < 1e-200 {
            let x = (1.0 + 2.0 * k / sigma) / (1.0 + k / g);
            return Some(PlasticZone {
                alpha: x.sqrt(),
                alpha_rate: 0.0,
            });
        }
        if q >= k {
            return None;
        }
        let a = q / sigma;
        let b_term = (1.0 + a) * (1.0 + a) * q;
        let c = k - q;
        let d = q / (2.0 * g);
        let a_minus_c = k * a * (2.0 + a) + q;
        let linear = 2.0 * c * d + b_term;
        let x = 2.0 * a_minus_c / (linear + (linear * linear + 4.0 * c * d * d * a_minus_c).sqrt());
        let alpha = x.sqrt();
        // Φ(x, q) = (1 + q/σ)² (K − q x) − (1 + q x/(2G))² (K − q).
        let e = 1.0 + q / sigma;
        let f = 1.0 + q * x / (2.0 * g);
        let phi_q = 2.0 / sigma * e * (k - q * x) - x * e * e - x / g * f * (k - q) + f * f;
        // Φ_x = −q W, W = (1 + q/σ)² + (1 + q x/(2G))(K − q)/G.
        let w = e * e + f * (k - q) / g;
        // dα/du = (Φ_q / (q W)) ρt u / α = Φ_q / (α u W).
        let alpha_rate = phi_q / (alpha * u * w);
        (alpha >= 1.0 && alpha.is_finite() && alpha_rate.is_finite())
            .then_some(PlasticZone { alpha, alpha_rate })
    }
}

impl WalkerAnderson {
    fn new(case: &RodTarget, crater_radius: Option<f64>) -> Result<Self, AnalyticError> {
        Ok(WalkerAnderson {
            rod_density: positive("rod density", case.rod_density)?,
            rod_strength: non_negative("rod strength", case.rod_strength)?,
            rod_wave_speed: positive("rod bar wave speed", case.rod_bar_wave_speed)?,
            target: TargetCavity::new(case)?,
            crater_radius: match crater_radius {
                Some(radius) => positive("crater radius", radius)?,
                None => default_crater_radius(case.rod_diameter, case.striking_velocity)?,
            },
        })
    }

    /// Right-hand side of Walker & Anderson (1995) for the state (v, u, L, P):
    ///
    /// v̇ = −σp/[ρp (L−s)] (1 + (v−u)/c + ṡ/c),
    /// u̇ [ρp s + ρt R (α−1)/(α+1)] = ½ρp(v−u)² − ½ρt u² − (7/3) σt ln α − ρp v̇ (L−s)
    ///     − ½ρp s² d/dt[(v−u)/s] − 2ρt R u α̇/(α+1)²,
    /// s = (R/2)(v/u − 1)(1 − α⁻²), L̇ = −(v−u), Ṗ = u.
    ///
    /// The time derivatives of the algebraic quantities are expressed exactly by the chain rule
    /// in terms of u̇ and v̇: α̇ = α'(u) u̇; (v−u)/s = 2uα²/[R(α²−1)] does not depend on v, so
    /// d/dt[(v−u)/s] = (2/R)[α²/(α²−1) − 2uαα'/(α²−1)²] u̇; ṡ = ∂s/∂v v̇ + ∂s/∂u u̇ (with α(u)).
    /// The two equations are then linear in (v̇, u̇) and solved exactly (Cramer); no lagged
    /// derivatives are used (unlike `awcsc`, which averages with the previous step's).
    ///
    /// Domain (else None): u > 0, v > u (an eroding rod), s < L (an undeformed rod section is
    /// left), α defined, and a positive determinant of the 2×2 system.
    fn rhs(&self, state: &[f64; 4]) -> Option<[f64; 4]> {
        let [v, u, length, _depth] = *state;
        if !(u > 0.0 && v > u && length > 0.0) {
            return None;
        }
        let (rp, rt) = (self.rod_density, self.target.density);
        let radius = self.crater_radius;
        let c = self.rod_wave_speed;
        let PlasticZone { alpha, alpha_rate } = self.target.plastic_zone(u)?;
        let alpha_sq_minus_one = alpha * alpha - 1.0;
        if alpha_sq_minus_one <= 0.0 {
            return None;
        }
        let shape = alpha_sq_minus_one / (alpha * alpha);
        let s = 0.5 * radius * (v / u - 1.0) * shape;
        let undeformed = length - s;
        if undeformed.is_nan() || undeformed <= 0.0 {
            return None;
        }
        let ds_dv = 0.5 * radius * shape / u;
        let ds_du = 0.5
            * radius
            * (-(v / (u * u)) * shape + (v / u - 1.0) * 2.0 * alpha_rate / (alpha * alpha * alpha));
        // d/dt[(v−u)/s] = ratio_rate · u̇.
        let ratio_rate = 2.0 / radius
            * (alpha * alpha / alpha_sq_minus_one
                - 2.0 * u * alpha * alpha_rate / (alpha_sq_minus_one * alpha_sq_minus_one));
        let nose_mass = rp * s
            + rt * radius * (alpha - 1.0) / (alpha + 1.0)
            + 0.5 * rp * s * s * ratio_rate
            + 2.0 * rt * radius * u * alpha_rate / ((alpha + 1.0) * (alpha + 1.0));
        let driving = 0.5 * rp * (v - u) * (v - u)
            - 0.5 * rt * u * u
            - 7.0 / 3.0 * self.target.strength * libm::log(alpha);
        // Rod:  (1 + κ ∂s/∂v) v̇ + κ ∂s/∂u u̇ = −κ (c + v − u),  κ = σp/(ρp (L−s) c);
        // nose: ρp (L−s) v̇ + nose_mass u̇ = driving.
        let kappa = self.rod_strength / (rp * undeformed * c);
        let (a11, a12, b1) = (1.0 + kappa * ds_dv, kappa * ds_du, -kappa * (c + v - u));
        let (a21, a22, b2) = (rp * undeformed, nose_mass, driving);
        let determinant = a11 * a22 - a12 * a21;
        if !(determinant > 0.0 && determinant.is_finite()) {
            return None;
        }
        let v_rate = (b1 * a22 - a12 * b2) / determinant;
        let u_rate = (a11 * b2 - a21 * b1) / determinant;
        Some([v_rate, u_rate, -(v - u), u])
    }
}

/// Extent α of the target's plastic zone (in crater radii) at the penetration velocity u, from
/// Walker–Anderson's dynamic cavity expansion (1 + ρt u²/σt)² (K − ρt α² u²) =
/// (1 + ρt α² u²/(2G))² (K − ρt u²), the root α ≥ 1 (unique for σt < 2G and ρt u² < K). At
/// u = 0 the equation linearises to α² = (1 + 2K/σt)/(1 + K/G), which tends to the quasi-static
/// cavity expansion's 2G/σt for an incompressible target (K → ∞). Reads the target's density,
/// strength and moduli only.
pub fn walker_anderson_plastic_zone_extent(
    case: &RodTarget,
    penetration_velocity: f64,
) -> Result<f64, AnalyticError> {
    let target = TargetCavity::new(case)?;
    let u = non_negative("penetration velocity", penetration_velocity)?;
    target
        .plastic_zone(u)
        .map(|zone| zone.alpha)
        .ok_or_else(|| {
            AnalyticError::OutsideModel(format!(
                "ρt u² = {:.3e} Pa is not below the target bulk modulus",
                target.density * u * u
            ))
        })
}

/// Where a Walker–Anderson history stops describing a plate of `thickness`: the first sample
/// at which the target's plastic zone ahead of the nose, α(u) crater radii
/// ([`walker_anderson_plastic_zone_extent`], the crater radius by [`default_crater_radius`]),
/// reaches the plate's rear face, `P + α R >= thickness`. From then on the model's
/// semi-infinite target resists more than the plate does. Returns that sample's time, α and
/// the plastic zone's extent `α R` (m); `None` if the rear face stays outside it throughout.
pub fn rear_face_in_plastic_zone(
    case: &RodTarget,
    history: &[PenetrationSample],
    thickness: f64,
) -> Result<Option<(f64, f64, f64)>, AnalyticError> {
    let thickness = positive("target thickness", thickness)?;
    let radius = default_crater_radius(case.rod_diameter, case.striking_velocity)?;
    for sample in history {
        let alpha = walker_anderson_plastic_zone_extent(case, sample.penetration_velocity)?;
        if sample.nose_depth + alpha * radius >= thickness {
            return Ok(Some((sample.time, alpha, alpha * radius)));
        }
    }
    Ok(None)
}

/// History of the Walker–Anderson model (Int. J. Impact Eng. 16 (1995) 19–48):
///
/// v̇ = −σp/[ρp (L−s)] (1 + (v−u)/c + ṡ/c),
/// u̇ [ρp s + ρt R (α−1)/(α+1)] = ½ρp(v−u)² − ½ρt u² − (7/3) σt ln α − ρp v̇ (L−s)
///     − ½ρp s² d/dt[(v−u)/s] − 2ρt R u α̇/(α+1)²,
/// s = (R/2)(v/u − 1)(1 − α⁻²), L̇ = −(v−u), Ṗ = u,
///
/// with α from [`walker_anderson_plastic_zone_extent`], from v = V0, u = u0 by the Hugoniot
/// match ([`hugoniot_interface_velocity`]), L = L0, P = 0, with the crater radius R given or by
/// [`default_crater_radius`]. The derivatives ṡ, α̇ and d/dt[(v−u)/s] are taken exactly by the
/// chain rule through u̇ and v̇, and the resulting linear 2×2 system for (v̇, u̇) is solved at
/// every stage (no lagged derivatives).
///
/// The history ends at `end_time` or when the erosion phase ends: u → 0, v → u, or the rod's
/// plastic zone s reaching the rod's length (L − s → 0, where the rod deceleration becomes
/// singular). The secondary (rigid-body) penetration after that is neglected: it is small
/// for the long rods this model is meant for. Samples every `output_interval` and at the end.
/// Integration: RK4 at 1 ns ([`INTERNAL_STEP`]).
pub fn walker_anderson_history(
    case: &RodTarget,
    crater_radius: Option<f64>,
    end_time: f64,
    output_interval: f64,
) -> Result<Vec<PenetrationSample>, AnalyticError> {
    walker_anderson_history_with_step(
        case,
        crater_radius,
        end_time,
        output_interval,
        INTERNAL_STEP,
    )
}

fn walker_anderson_history_with_step(
    case: &RodTarget,
    crater_radius: Option<f64>,
    end_time: f64,
    output_interval: f64,
    max_step: f64,
) -> Result<Vec<PenetrationSample>, AnalyticError> {
    let model = WalkerAnderson::new(case, crater_radius)?;
    let length = positive("rod length", case.rod_length)?;
    let velocity = positive("striking velocity", case.striking_velocity)?;
    let u0 = hugoniot_interface_velocity(case)?;
    integrate(
        [velocity, u0, length, 0.0],
        |state| model.rhs(state),
        |time, &[v, u, length, depth]| PenetrationSample {
            time,
            nose_depth: depth,
            rod_length: length,
            rod_velocity: v,
            penetration_velocity: u,
        },
        end_time,
        output_interval,
        max_step,
    )
}

/// Quasi-steady penetration velocity of the Walker–Anderson model: the mean u over the window
/// in which the rod erodes from 30 % to 70 % of its length ([`quasi_steady_penetration_velocity`]),
/// from a history run until the erosion phase ends (at most 100 L0/V0) and sampled every
/// L0/(5000 V0).
pub fn walker_anderson_quasi_steady_penetration_velocity(
    case: &RodTarget,
    crater_radius: Option<f64>,
) -> Result<f64, AnalyticError> {
    let length = positive("rod length", case.rod_length)?;
    let velocity = positive("striking velocity", case.striking_velocity)?;
    let transit = length / velocity;
    let history = walker_anderson_history(case, crater_radius, 100.0 * transit, transit / 5000.0)?;
    quasi_steady_penetration_velocity(&history)
}

#[cfg(test)]
mod tests {
    use super::*;

    const RHO_WHA: f64 = 17600.0;
    const RHO_STEEL: f64 = 7850.0;

    /// Anderson, Hohler, Walker & Stilp (IJIE 16 (1995) 1): WHA rod Ø5 × 50 mm into HzB-W steel.
    fn wha_into_steel(striking_velocity: f64, rod_strength: f64) -> RodTarget {
        RodTarget {
            rod_density: RHO_WHA,
            rod_strength,
            rod_length: 0.05,
            rod_diameter: 0.005,
            rod_bar_wave_speed: (350.0e9_f64 / RHO_WHA).sqrt(),
            rod_hugoniot: TUNGSTEN_ALLOY_HUGONIOT,
            target_density: RHO_STEEL,
            target_strength: 1.45e9,
            target_resistance: 5.0e9,
            target_bulk_modulus: 160.0e9,
            target_shear_modulus: 80.0e9,
            target_hugoniot: STEEL_HUGONIOT,
            striking_velocity,
        }
    }

    #[test]
    fn the_rear_face_enters_the_plastic_zone_when_the_nose_is_one_zone_from_it() {
        // GOAL: the semi-infinite model's limit for a plate is found where its plastic zone
        // reaches the rear face, and not for a plate thicker than the zone ever reaches.
        // SETUP: seed 000's rod at 1700 m/s, Walker–Anderson to 60 us; plates of 49.5 mm
        // (the experiment), 5 m and 1 mm.
        // REFERENCE: the condition P + alpha R >= thickness itself, checked on the samples
        // either side of the reported time; alpha from the dynamic cavity expansion (>= 1).
        let case = wha_into_steel(1700.0, 1.5e9);
        let history = walker_anderson_history(&case, None, 60.0e-6, 0.5e-6).unwrap();
        let radius = default_crater_radius(case.rod_diameter, case.striking_velocity).unwrap();
        let (time, alpha, extent) = rear_face_in_plastic_zone(&case, &history, 0.0495)
            .unwrap()
            .expect("the zone reaches a 49.5 mm plate's rear face");
        assert!(alpha >= 1.0 && (extent - alpha * radius).abs() < 1e-15);
        let k = history.iter().position(|s| s.time == time).unwrap();
        assert!(k > 0, "not at impact");
        let reach = |s: &PenetrationSample| {
            s.nose_depth
                + walker_anderson_plastic_zone_extent(&case, s.penetration_velocity).unwrap()
                    * radius
        };
        assert!(reach(&history[k]) >= 0.0495 && reach(&history[k - 1]) < 0.0495);
        assert_eq!(
            rear_face_in_plastic_zone(&case, &history, 5.0).unwrap(),
            None
        );
        let thin = rear_face_in_plastic_zone(&case, &history, 1.0e-3)
            .unwrap()
            .unwrap();
        assert_eq!(thin.0, history[0].time);
        assert!(rear_face_in_plastic_zone(&case, &history, 0.0).is_err());
    }

    fn tate_case(striking_velocity: f64, rod_strength: f64, target_resistance: f64) -> RodTarget {
        RodTarget {
            target_resistance,
            ..wha_into_steel(striking_velocity, rod_strength)
        }
    }

    fn relative(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn tate_steady_velocity_matches_the_closed_form() {
        // GOAL: the robust root of the modified Bernoulli equation is the textbook one, in
        //       all three regimes and for equal densities.
        // SETUP: WHA/steel, Yp 1 GPa, Rt 5 GPa, v 1700 m/s; equal densities 7850; u = 0 and
        //        rigid cases.
        // REFERENCE: u = [v − μ√(v² + A)]/(1 − μ²), μ = √(ρt/ρp), A = 2(Rt−Yp)(1−μ²)/ρt
        //   (Anderson & Walker's form), by hand (Python): 828.0211471680373 m/s. Equal
        //   densities: u = v/2 + (Yp−Rt)/(ρ v). u = 0 iff ½ρp v² + Yp ≤ Rt; u = v iff
        //   Yp ≥ Rt + ½ρt v².
        let case = tate_case(1700.0, 1.0e9, 5.0e9);
        let u = tate_steady_penetration_velocity(&case, 1700.0).unwrap();
        assert!(relative(u, 828.021_147_168_037_3) < 1e-13, "u = {u}");
        let bernoulli =
            0.5 * RHO_WHA * (1700.0 - u).powi(2) + 1.0e9 - 0.5 * RHO_STEEL * u * u - 5.0e9;
        assert!(bernoulli.abs() < 1e-6 * 5.0e9);

        let equal = RodTarget {
            rod_density: RHO_STEEL,
            ..case
        };
        let u = tate_steady_penetration_velocity(&equal, 1700.0).unwrap();
        let expected = 850.0 + (1.0e9 - 5.0e9) / (RHO_STEEL * 1700.0);
        assert!(relative(u, expected) < 1e-13, "{u} vs {expected}");

        // u = 0: ½ 17600 500² + 1 GPa = 3.2 GPa < 20 GPa.
        let blocked = tate_case(500.0, 1.0e9, 20.0e9);
        assert_eq!(
            tate_steady_penetration_velocity(&blocked, 500.0).unwrap(),
            0.0
        );
        // u = v: 10 GPa ≥ 1 GPa + ½ 7850 200² = 1.157 GPa.
        let rigid = tate_case(200.0, 10.0e9, 1.0e9);
        assert_eq!(
            tate_steady_penetration_velocity(&rigid, 200.0).unwrap(),
            200.0
        );
        // Hydrodynamic: u = v/(1 + μ).
        let hydro = tate_case(1700.0, 0.0, 0.0);
        let u = tate_steady_penetration_velocity(&hydro, 1700.0).unwrap();
        let expected = 1700.0 / (1.0 + (RHO_STEEL / RHO_WHA).sqrt());
        assert!(relative(u, expected) < 1e-13);
    }

    #[test]
    fn tate_reproduces_the_hydrodynamic_and_rigid_body_limits() {
        // GOAL: the integrated history ends at the closed-form depths of its two limits.
        // SETUP: (1) Yp = Rt = 0, V0 1700, L0 50 mm; (2) rigid: Yp 10 GPa, Rt 1 GPa, V0 200;
        //        (3) non-penetrating: Yp 1 GPa, Rt 20 GPa, V0 500.
        // REFERENCE: (1) P/L0 = √(ρp/ρt) (Birkhoff et al. 1948); (2) ρp L v dv/dP =
        //   −(Rt + ½ρt v²) ⇒ P = (ρp L0/ρt) ln(1 + ρt V0²/(2 Rt)) = 0.016347871901420993 m;
        //   (3) P = 0 and the rod stops at L = L0 exp(−ρp V0²/(2 Yp)) = 0.005540157918116694 m.
        let hydro = tate_history(&tate_case(1700.0, 0.0, 0.0), 1.0e-3, 1.0e-6).unwrap();
        let ratio = hydrodynamic_depth_ratio(RHO_WHA, RHO_STEEL).unwrap();
        let last = hydro.last().unwrap();
        assert!(relative(last.nose_depth, 0.05 * ratio) < 1e-6, "{last:?}");
        assert!(last.rod_length < 1e-6 * 0.05);

        let rigid = tate_history(&tate_case(200.0, 10.0e9, 1.0e9), 1.0e-3, 1.0e-6).unwrap();
        let last = rigid.last().unwrap();
        assert!(
            relative(last.nose_depth, 0.016_347_871_901_420_993) < 1e-6,
            "{last:?}"
        );
        assert_eq!(last.rod_length, 0.05);
        assert!(last.rod_velocity.abs() < 1e-3);

        let blocked = tate_history(&tate_case(500.0, 1.0e9, 20.0e9), 1.0e-3, 1.0e-6).unwrap();
        let last = blocked.last().unwrap();
        assert_eq!(last.nose_depth, 0.0);
        assert!(
            relative(last.rod_length, 0.005_540_157_918_116_694) < 1e-5,
            "{last:?}"
        );
    }

    /// Rt giving Tate's depth 4.56 cm at 60.3 µs for 1700 m/s (bisection to 1e-7 relative).
    fn tate_fitted_resistance(rod_strength: f64) -> f64 {
        let depth = |resistance: f64| {
            let history = tate_history(
                &tate_case(1700.0, rod_strength, resistance),
                60.3e-6,
                0.1e-6,
            )
            .unwrap();
            depth_at(&history, 60.3e-6)
        };
        let (mut low, mut high) = (1.0e9, 15.0e9);
        while high - low > 1e-7 * high {
            let mid = 0.5 * (low + high);
            if depth(mid) > 0.0456 {
                low = mid;
            } else {
                high = mid;
            }
        }
        0.5 * (low + high)
    }

    #[test]
    fn tate_fit_to_the_anderson_experiments_matches_the_euler_check_script() {
        // GOAL: RK4 Tate agrees with the research check script; the fitted Rt and the predicted
        //       depth at 1250 m/s are those quoted in experiments.md §1.
        // SETUP: ρp 17600, ρt 7850, L0 50 mm; Yp 1.0/1.5/2.0 GPa; Rt fitted so that the depth at
        //        60.3 µs for 1700 m/s is 4.56 cm; then the depth at 55 µs for 1250 m/s.
        // REFERENCE: /work/shared/research/checks/tate.py (explicit Euler, 1 ns, brentq), run
        //   with more digits: Rt = 5.025656 / 5.329242 / 5.526783 GPa, P(55 µs) = 2.527132 /
        //   2.493461 / 2.502673 cm. The first-order Euler scheme at 1 ns differs from RK4 by
        //   ~1e-4 relative here (observed 0.5e-4 in Rt, 0.2e-4 in depth); tolerance 0.1 %.
        let reference = [
            (1.0e9, 5.025656e9, 0.02527132),
            (1.5e9, 5.329242e9, 0.02493461),
            (2.0e9, 5.526783e9, 0.02502673),
        ];
        for (rod_strength, resistance_ref, depth_ref) in reference {
            let resistance = tate_fitted_resistance(rod_strength);
            let history = tate_history(
                &tate_case(1250.0, rod_strength, resistance),
                55.0e-6,
                0.1e-6,
            )
            .unwrap();
            let depth = depth_at(&history, 55.0e-6);
            println!(
                "Tate Yp {:.1} GPa: fitted Rt {:.4} GPa (Euler {:.4}), P(55 us, 1250 m/s) {:.4} cm \
                 (Euler {:.4})",
                rod_strength / 1e9,
                resistance / 1e9,
                resistance_ref / 1e9,
                depth * 100.0,
                depth_ref * 100.0
            );
            assert!(relative(resistance, resistance_ref) < 1e-3);
            assert!(relative(depth, depth_ref) < 1e-3);
            // And at the Euler script's own Rt, the 1700 m/s depth is its 4.56 cm.
            let history = tate_history(
                &tate_case(1700.0, rod_strength, resistance_ref),
                60.3e-6,
                0.1e-6,
            )
            .unwrap();
            assert!(relative(depth_at(&history, 60.3e-6), 0.0456) < 1e-3);
        }
    }

    #[test]
    fn tate_resistance_estimate_is_tates_formula() {
        // GOAL: Rt ≈ σt (2/3 + ln(0.57 E/σt)). SETUP: σt 1.45 GPa, E 210 GPa.
        // REFERENCE: by hand: 1.45 (0.666667 + ln 82.5517) = 1.45 × 5.07995 = 7.3659 GPa.
        let rt = tate_resistance_estimate(1.45e9, 210.0e9).unwrap();
        let expected = 1.45e9 * (2.0 / 3.0 + (0.57_f64 * 210.0 / 1.45).ln());
        assert!(relative(rt, expected) < 1e-14);
        assert!(relative(rt, 7.3659e9) < 1e-4, "{rt}");
        assert!(tate_resistance_estimate(1.45e9, 1.0e9).is_err());
    }

    #[test]
    fn plastic_zone_solves_the_cavity_equation_and_has_the_quasi_static_limit() {
        // GOAL: α solves the dynamic cavity expansion equation; dα/du is its derivative; the
        //       u → 0 limit is the linearised one.
        // SETUP: steel σt 1.45 GPa, K 160 GPa, G 80 GPa, ρt 7850; u = 1e-3 … 1500 m/s.
        // REFERENCE: the equation itself (residual), central finite differences of α(u), and
        //   α² = (1 + 2K/σt)/(1 + K/G) = 73.896... at u → 0 (derived by expanding both sides
        //   to first order in ρt u²).
        let case = wha_into_steel(1700.0, 1.0e9);
        let model = TargetCavity::new(&case).unwrap();
        let (k, g, sigma, rho) = (160.0e9, 80.0e9, 1.45e9, RHO_STEEL);
        for u in [1.0e-3, 1.0, 100.0, 500.0, 900.0, 1500.0] {
            let zone = model.plastic_zone(u).unwrap();
            let x = zone.alpha * zone.alpha;
            let q = rho * u * u;
            let lhs = (1.0 + q / sigma).powi(2) * (k - q * x);
            let rhs = (1.0 + q * x / (2.0 * g)).powi(2) * (k - q);
            assert!(
                (lhs - rhs).abs() < 1e-12 * lhs.abs().max(rhs.abs()),
                "u {u}"
            );
            if u >= 1.0 {
                let h = 1e-4 * u;
                let numeric = (model.plastic_zone(u + h).unwrap().alpha
                    - model.plastic_zone(u - h).unwrap().alpha)
                    / (2.0 * h);
                assert!(
                    (zone.alpha_rate - numeric).abs() < 1e-6 * numeric.abs().max(1e-6),
                    "u {u}: {} vs {numeric}",
                    zone.alpha_rate
                );
            }
        }
        let limit = ((1.0 + 2.0 * k / sigma) / (1.0 + k / g)).sqrt();
        let alpha0 = walker_anderson_plastic_zone_extent(&case, 0.0).unwrap();
        assert_eq!(alpha0, limit);
        assert!(relative(model.plastic_zone(1.0e-3).unwrap().alpha, limit) < 1e-9);
        // α falls as the penetration speeds up.
        assert!(
            model.plastic_zone(900.0).unwrap().alpha < model.plastic_zone(300.0).unwrap().alpha
        );
    }

    #[test]
    fn hugoniot_match_balances_the_two_shock_pressures() {
        // GOAL: u0 equalises rod and target shock pressures.
        // SETUP: WHA on steel at 1700 m/s. REFERENCE: the linear Hugoniots' pressures, equal to
        //   1e-9 relative; u0 ≈ 1080 m/s by hand (rod 52.3 GPa vs target 52.4 GPa at 1080).
        let case = wha_into_steel(1700.0, 1.0e9);
        let u0 = hugoniot_interface_velocity(&case).unwrap();
        let rod = RHO_WHA * (4029.0 + 1.237 * (1700.0 - u0)) * (1700.0 - u0);
        let target = RHO_STEEL * (4570.0 + 1.49 * u0) * u0;
        assert!(relative(rod, target) < 1e-9);
        assert!((u0 - 1080.0).abs() < 5.0, "{u0}");
    }

    #[test]
    fn walker_anderson_reproduces_the_anderson_1995_experiments() {
        // GOAL: the time-dependent model follows the measured nose depths of the WHA/steel tests.
        // SETUP: WHA Ø5 × 50 mm (17600, σp 1.0/1.5/2.0 GPa, c = √(350 GPa/17600)) into steel
        //        (7850, σt 1.45 GPa, K 160, G 80 GPa), default crater radius; 1700 m/s read at
        //        60.3 µs, 1250 m/s at 55 µs.
        // REFERENCE: Anderson, Hohler, Walker & Stilp, IJIE 16 (1995) 1: 4.56 cm and 2.32 cm
        //   (experiments.md §1); Walker & Anderson (IJIE 16 (1995) 19) show the model follows
        //   these; tolerances 15 % and 20 % (the brief's; the model misses the target's finite
        //   thickness at 1250 m/s and the crater-radius fit is generic).
        for rod_strength in [1.0e9, 1.5e9, 2.0e9] {
            let fast = walker_anderson_history(
                &wha_into_steel(1700.0, rod_strength),
                None,
                60.3e-6,
                0.1e-6,
            )
            .unwrap();
            let slow = walker_anderson_history(
                &wha_into_steel(1250.0, rod_strength),
                None,
                55.0e-6,
                0.1e-6,
            )
            .unwrap();
            let (p_fast, p_slow) = (depth_at(&fast, 60.3e-6), depth_at(&slow, 55.0e-6));
            let u_qs = walker_anderson_quasi_steady_penetration_velocity(
                &wha_into_steel(1700.0, rod_strength),
                None,
            )
            .unwrap();
            let u_qs_slow = walker_anderson_quasi_steady_penetration_velocity(
                &wha_into_steel(1250.0, rod_strength),
                None,
            )
            .unwrap();
            println!(
                "WA sigma_p {:.1} GPa: P(60.3 us, 1700) = {:.3} cm (meas 4.56), P(55 us, 1250) = \
                 {:.3} cm (meas 2.32); quasi-steady u {:.1} m/s (1700), {:.1} m/s (1250)",
                rod_strength / 1e9,
                p_fast * 100.0,
                p_slow * 100.0,
                u_qs,
                u_qs_slow
            );
            assert!(relative(p_fast, 0.0456) < 0.15);
            assert!(relative(p_slow, 0.0232) < 0.20);
        }
    }

    #[test]
    fn walker_anderson_quasi_steady_ratio_lies_between_tate_bounds() {
        // GOAL: in the quasi-steady window u/v lies between the Tate value with the largest
        //       (quasi-static) Walker–Anderson target resistance and the hydrodynamic value.
        // SETUP: WHA/steel, σp 1.0 and 2.0 GPa, 1250 and 1700 m/s; every sample with 30–70 %
        //        of the rod eroded.
        // REFERENCE: in quasi-steady flow (u̇ ≈ 0) WA reduces to ½ρp(v−u)² + σp(1 + (v−u)/c) =
        //   ½ρt u² + (7/3)σt ln α(u), a Tate equation with Yp ≥ σp and Rt ≤ (7/3)σt ln α(0),
        //   so u/v is above Tate's with (σp, (7/3)σt ln α(0)); and since that Rt exceeds Yp
        //   here, u/v is below the hydrodynamic 1/(1 + √(ρt/ρp)) = 0.5996. (The brief asked
        //   for "between the hydrodynamic value and 1": that holds only when the rod is
        //   stronger than the target's resistance, not for WHA into armour steel.)
        let hydro = 1.0 / (1.0 + (RHO_STEEL / RHO_WHA).sqrt());
        for rod_strength in [1.0e9, 2.0e9] {
            for striking_velocity in [1250.0, 1700.0] {
                let case = wha_into_steel(striking_velocity, rod_strength);
                let alpha0 = walker_anderson_plastic_zone_extent(&case, 0.0).unwrap();
                let bound = RodTarget {
                    target_resistance: 7.0 / 3.0 * 1.45e9 * alpha0.ln(),
                    ..case
                };
                let history = walker_anderson_history(&case, None, 200.0e-6, 0.1e-6).unwrap();
                let (start, end) = quasi_steady_window(&history).unwrap();
                let mut checked = 0;
                for sample in history
                    .iter()
                    .filter(|s| s.time >= start.time && s.time <= end.time)
                {
                    let v = sample.rod_velocity;
                    let ratio = sample.penetration_velocity / v;
                    let lower = tate_steady_penetration_velocity(&bound, v).unwrap() / v;
                    assert!(
                        lower < ratio && ratio < hydro,
                        "{lower} < {ratio} < {hydro}"
                    );
                    checked += 1;
                }
                assert!(checked > 50);
            }
        }
    }

    #[test]
    fn walker_anderson_histories_are_monotone() {
        // GOAL: the nose only advances and the rod only shortens.
        // SETUP: WHA/steel, σp 1.5 GPa, 1250 and 1700 m/s, to the end of the erosion phase.
        // REFERENCE: Ṗ = u > 0 and L̇ = −(v − u) < 0 in the model's domain.
        for striking_velocity in [1250.0, 1700.0] {
            let history = walker_anderson_history(
                &wha_into_steel(striking_velocity, 1.5e9),
                None,
                200.0e-6,
                0.1e-6,
            )
            .unwrap();
            assert!(history.len() > 100);
            for pair in history.windows(2) {
                assert!(pair[1].time > pair[0].time);
                assert!(pair[1].nose_depth > pair[0].nose_depth);
                assert!(pair[1].rod_length < pair[0].rod_length);
            }
            let last = history.last().unwrap();
            assert!(last.time < 200.0e-6, "the erosion phase ends before 200 us");
        }
    }

    #[test]
    fn walker_anderson_tends_to_hydrodynamic_penetration_without_strength() {
        // GOAL: with negligible strengths the quasi-steady u is Bernoulli's.
        // SETUP: WHA/steel at 1700 m/s with σp = σt = 10 kPa.
        // REFERENCE: ½ρp(v−u)² = ½ρt u², v = V0 ⇒ u = V0/(1 + √(ρt/ρp)) = 1019.28 m/s; the
        //   remaining inertia terms (ρp s, ρt R (α−1)/(α+1)) vanish in steady flow; 2 %.
        let case = RodTarget {
            target_strength: 1.0e4,
            ..wha_into_steel(1700.0, 1.0e4)
        };
        let u = walker_anderson_quasi_steady_penetration_velocity(&case, None).unwrap();
        let expected = 1700.0 / (1.0 + (RHO_STEEL / RHO_WHA).sqrt());
        println!("WA strengthless quasi-steady u = {u:.2} m/s (Bernoulli {expected:.2})");
        assert!(relative(u, expected) < 0.02, "{u} vs {expected}");
    }

    #[test]
    fn walker_anderson_converges_with_the_time_step() {
        // GOAL: the 1 ns internal step is converged. SETUP: WHA/steel, σp 1.5 GPa, 1700 m/s.
        // REFERENCE: the same run at 0.25 ns; depths at 60.3 µs agree to 1e-6 relative.
        let case = wha_into_steel(1700.0, 1.5e9);
        let coarse =
            walker_anderson_history_with_step(&case, None, 60.3e-6, 0.1e-6, 1.0e-9).unwrap();
        let fine =
            walker_anderson_history_with_step(&case, None, 60.3e-6, 0.1e-6, 0.25e-9).unwrap();
        let (a, b) = (depth_at(&coarse, 60.3e-6), depth_at(&fine, 60.3e-6));
        assert!(relative(a, b) < 1e-6, "{a} vs {b}");
    }

    #[test]
    fn depth_at_interpolates_and_holds_the_ends() {
        // GOAL: linear interpolation inside, end values outside. SETUP: two samples.
        // REFERENCE: by hand.
        let sample = |time, nose_depth| PenetrationSample {
            time,
            nose_depth,
            rod_length: 0.05,
            rod_velocity: 1.0,
            penetration_velocity: 1.0,
        };
        let history = [sample(0.0, 0.0), sample(1.0, 2.0), sample(2.0, 3.0)];
        assert_eq!(depth_at(&history, 0.25), 0.5);
        assert_eq!(depth_at(&history, 1.5), 2.5);
        assert_eq!(depth_at(&history, 1.0), 2.0);
        assert_eq!(depth_at(&history, -1.0), 0.0);
        assert_eq!(depth_at(&history, 9.0), 3.0);
        assert!(depth_at(&[], 1.0).is_nan());
        assert!(quasi_steady_penetration_velocity(&history).is_err());
    }

    #[test]
    fn non_physical_inputs_are_rejected() {
        // GOAL: bad inputs give typed errors, not panics or NaN histories.
        // SETUP: one bad field at a time. REFERENCE: AnalyticError variants.
        let good = wha_into_steel(1700.0, 1.0e9);
        let bad = |case: RodTarget| {
            (
                tate_history(&case, 1e-6, 1e-7).is_err(),
                walker_anderson_history(&case, None, 1e-6, 1e-7).is_err(),
            )
        };
        assert_eq!(bad(good), (false, false));
        assert_eq!(
            bad(RodTarget {
                rod_density: 0.0,
                ..good
            }),
            (true, true)
        );
        assert_eq!(
            bad(RodTarget {
                rod_length: -1.0,
                ..good
            }),
            (true, true)
        );
        assert_eq!(
            bad(RodTarget {
                striking_velocity: f64::NAN,
                ..good
            }),
            (true, true)
        );
        assert_eq!(
            bad(RodTarget {
                rod_strength: -1.0,
                ..good
            }),
            (true, true)
        );
        assert_eq!(
            bad(RodTarget {
                target_resistance: -1.0,
                ..good
            }),
            (true, false)
        );
        assert_eq!(
            bad(RodTarget {
                target_strength: 0.0,
                ..good
            }),
            (false, true)
        );
        assert_eq!(
            bad(RodTarget {
                target_strength: 200.0e9,
                ..good
            }),
            (false, true)
        );
        assert_eq!(
            bad(RodTarget {
                rod_diameter: f64::INFINITY,
                ..good
            }),
            (false, true)
        );
        assert_eq!(
            bad(RodTarget {
                rod_hugoniot: (0.0, 1.0),
                ..good
            }),
            (false, true)
        );
        assert!(matches!(
            tate_history(&good, -1.0, 1e-7),
            Err(AnalyticError::NotPositive { .. })
        ));
        assert!(tate_history(&good, 1.0, 1e-12).is_err());
        assert!(walker_anderson_history(&good, Some(0.0), 1e-6, 1e-7).is_err());
        assert!(hydrodynamic_depth_ratio(-1.0, 1.0).is_err());
        let text = AnalyticError::NotPositive {
            quantity: "rod density",
            value: 0.0,
        }
        .to_string();
        assert_eq!(text, "rod density must be positive, got 0");
    }

    #[test]
    fn hills_spherical_cavity_pressure_is_four_thirds_y_when_the_logarithm_is_one() {
        // GOAL: the moduli reach Hill's formula as E and nu.
        // SETUP: Y 1, nu 0.25 and E = 3 (1 - nu) Y e, i.e. K = E / (3 (1 - 2 nu)) = 1.5 e and
        //        G = E / (2 (1 + nu)) = 0.9 e, so that ln(E / (3 (1 - nu) Y)) = 1.
        // REFERENCE: sigma_s = 2/3 Y (1 + 1) = 4/3.
        let e = core::f64::consts::E;
        let pressure = spherical_cavity_pressure(1.0, 1.5 * e, 0.9 * e);
        assert!((pressure - 4.0 / 3.0).abs() < 1e-12, "{pressure}");
    }

    #[test]
    fn the_rigid_projectile_stops_where_and_when_the_closed_forms_say() {
        // GOAL: the integrated rigid-projectile history ends at the closed-form depth and time.
        // SETUP: 17 g, 2.5 mm radius, hemispherical nose, 800 m/s into steel (7850 kg/m3,
        //        sigma_s 5.15 GPa, B 3/2), sampled every 1 us to 200 us.
        // REFERENCE: m dV/dt = -A (R + c V^2) gives P = m / (2 A c) ln(1 + c V0^2 / R) and
        //            t = m / (A sqrt(R c)) atan(V0 sqrt(c / R)), c = N B rho.
        let projectile = RigidProjectile {
            mass: 0.017,
            radius: 2.5e-3,
            nose_factor: ogive_nose_factor(0.5),
            target_density: 7850.0,
            static_resistance: 5.15e9,
            inertial_coefficient: INCOMPRESSIBLE_INERTIAL_COEFFICIENT,
            striking_velocity: 800.0,
        };
        let history = rigid_projectile_history(&projectile, 200e-6, 1e-6).unwrap();
        let last = history.last().unwrap();
        let area = core::f64::consts::PI * 2.5e-3 * 2.5e-3;
        let c = 0.5 * 1.5 * 7850.0;
        let depth = 0.017 / (2.0 * area * c) * (1.0 + c * 800.0 * 800.0 / 5.15e9).ln();
        let time = 0.017 / (area * (5.15e9 * c).sqrt()) * (800.0 * (c / 5.15e9).sqrt()).atan();
        assert!(
            (last.nose_depth / depth - 1.0).abs() < 1e-6,
            "{} {depth}",
            last.nose_depth
        );
        assert!((projectile.final_depth().unwrap() / depth - 1.0).abs() < 1e-12);
        assert!(
            (last.time / time - 1.0).abs() < 1e-4,
            "{} {time}",
            last.time
        );
        assert!(last.rod_velocity.abs() < 1e-3, "{}", last.rod_velocity);
        assert!(history
            .windows(2)
            .all(|w| w[1].nose_depth >= w[0].nose_depth));
    }

    #[test]
    fn a_half_caliber_ogive_is_a_hemisphere_and_bad_projectiles_are_refused() {
        // GOAL: the ogive's nose factor is the hemisphere's where the shapes agree and falls
        //       as the nose sharpens; bad inputs give typed errors.
        // SETUP: caliber-radius-heads 1/2 (the arc is the hemisphere), 3 and 30; a zero mass, a
        //        negative velocity, a NaN resistance, no inertial term.
        // REFERENCE: N = (8 psi - 1) / (24 psi^2) (Forrestal, Okajima & Luk 1988): 1/2 at
        //            psi = 1/2, 23/216 at 3, about 1/(3 psi) for a slender nose.
        assert_eq!(ogive_nose_factor(0.5), 0.5);
        assert!((ogive_nose_factor(3.0) - 23.0 / 216.0).abs() < 1e-15);
        assert!((ogive_nose_factor(30.0) * 90.0 - 1.0).abs() < 0.01);
        let good = RigidProjectile {
            mass: 0.017,
            radius: 2.5e-3,
            nose_factor: 0.5,
            target_density: 7850.0,
            static_resistance: 5.15e9,
            inertial_coefficient: 1.5,
            striking_velocity: 800.0,
        };
        for bad in [
            RigidProjectile { mass: 0.0, ..good },
            RigidProjectile {
                striking_velocity: -1.0,
                ..good
            },
            RigidProjectile {
                static_resistance: f64::NAN,
                ..good
            },
            RigidProjectile {
                inertial_coefficient: 0.0,
                ..good
            },
        ] {
            assert!(rigid_projectile_history(&bad, 1e-5, 1e-6).is_err());
            assert!(bad.final_depth().is_err());
        }
    }
}
