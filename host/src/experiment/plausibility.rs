//! Recordings checked against their experiment at load: values a test cannot have produced
//! (a unit slip, an impossible history, a position outside the model) are refused, naming the
//! file, line and column, instead of being fitted silently.
//!
//! A bound set by the physics of the test (a rod cannot grow, a nose cannot move back, a
//! projectile cannot leave faster than it struck) is applied with the point's own recorded
//! uncertainty: a value is refused only if it lies more than [`NOISE_SIGMAS`] uncertainties
//! beyond the bound (for a history, beyond an earlier point by that many combined
//! uncertainties), so digitisation scatter passes and slips do not. Positions, which carry no
//! uncertainty, must lie inside the model: a time within `0..=end_time`, a radius within the
//! plate, a station inside the rod. The rules per kind are listed in docs/formats.md
//! ("Recordings checked against their experiment").

use super::Setup;
use crate::input::recording::RecordedPoint;

/// Recorded uncertainties by which a value may pass a physical bound (digitisation scatter).
pub const NOISE_SIGMAS: f64 = 3.0;

/// Plausible flow stress of a metal or strength of a concrete (Pa): below 1 MPa a stress given
/// in MPa was read as Pa; above 20 GPa one in kPa or psi was read as Pa.
pub const STRESS_RANGE: [f64; 2] = [1.0e6, 2.0e10];

/// A recording point that breaks a rule: its index, the column (`value` or `position`) and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Implausible {
    /// Index of the point in the recording.
    pub index: usize,
    /// `value` or `position`.
    pub column: &'static str,
    /// What is wrong, in words.
    pub message: String,
}

fn refuse(index: usize, column: &'static str, message: String) -> Option<Implausible> {
    Some(Implausible {
        index,
        column,
        message,
    })
}

/// `value` passes a lower bound `bound` within the point's noise.
fn at_least(point: &RecordedPoint, bound: f64) -> bool {
    point.value >= bound - NOISE_SIGMAS * point.uncertainty
}

/// `value` passes an upper bound `bound` within the point's noise.
fn at_most(point: &RecordedPoint, bound: f64) -> bool {
    point.value <= bound + NOISE_SIGMAS * point.uncertainty
}

/// The first point of `quantity` that breaks monotonicity in its position (`rising`: may not
/// fall; else may not rise) by more than the two points' combined noise.
fn monotone(recording: &[RecordedPoint], quantity: &str, rising: bool) -> Option<Implausible> {
    let mut points: Vec<(usize, &RecordedPoint)> = recording
        .iter()
        .enumerate()
        .filter(|(_, p)| p.quantity == quantity)
        .collect();
    points.sort_by(|a, b| a.1.position.total_cmp(&b.1.position));
    for (k, &(index, later)) in points.iter().enumerate() {
        for &(_, earlier) in &points[..k] {
            if earlier.position == later.position {
                continue;
            }
            let noise = NOISE_SIGMAS * libm::hypot(earlier.uncertainty, later.uncertainty);
            let change = later.value - earlier.value;
            let broken = if rising {
                change < -noise
            } else {
                change > noise
            };
            if broken {
                return refuse(
                    index,
                    "value",
                    format!(
                        "{quantity} {} at {} {} the {} recorded earlier at {}: a {quantity} \
                         {} with time",
                        later.value,
                        later.position,
                        if rising { "falls below" } else { "rises above" },
                        earlier.value,
                        earlier.position,
                        if rising { "cannot fall" } else { "cannot grow" }
                    ),
                );
            }
        }
    }
    None
}

/// At most one point of `quantity` (a single result of the test).
fn single(recording: &[RecordedPoint], quantity: &str) -> Option<Implausible> {
    let mut seen = false;
    for (index, point) in recording.iter().enumerate() {
        if point.quantity == quantity {
            if seen {
                return refuse(
                    index,
                    "value",
                    format!("a second {quantity}: one test has one"),
                );
            }
            seen = true;
        }
    }
    None
}

/// The first point of `recording` that `setup` could not have produced (see the module's
/// rules), or `None`.
pub fn check(setup: &Setup, recording: &[RecordedPoint]) -> Option<Implausible> {
    let [low, high] = STRESS_RANGE;
    let stress = |index: usize, point: &RecordedPoint, what: &str| {
        if (low..=high).contains(&point.value) {
            None
        } else {
            let why = if point.value <= 0.0 {
                "a stress magnitude is positive".to_string()
            } else if point.value < low {
                "below 1 MPa: a value in MPa read as Pa? write `value [MPa]` in the header"
                    .to_string()
            } else {
                "above 20 GPa: check the unit in the header".to_string()
            };
            refuse(index, "value", format!("{what} {} Pa: {why}", point.value))
        }
    };
    let inside = |index: usize, point: &RecordedPoint, end: f64, what: &str| {
        if (0.0..=end).contains(&point.position) {
            None
        } else {
            refuse(
                index,
                "position",
                format!("{what} {} is outside 0..={end}", point.position),
            )
        }
    };
    for (index, point) in recording.iter().enumerate() {
        let found = match (setup, point.quantity.as_str()) {
            (Setup::Uniaxial(_), "true_stress" | "peak_stress") => {
                stress(index, point, "a flow stress of")
            }
            (Setup::Tension(_), "axial_stress") => stress(index, point, "an axial stress of"),
            (Setup::Shpb(_), "engineering_stress") => {
                if point.value < 0.0 || point.value > high {
                    refuse(
                        index,
                        "value",
                        format!(
                            "an engineering stress of {} Pa (compressive positive) is outside \
                             0..={high}",
                            point.value
                        ),
                    )
                } else if !(0.0..1.0).contains(&point.position) {
                    refuse(
                        index,
                        "position",
                        format!(
                            "an engineering strain of {} is outside 0..1 (a strain in \
                             percent?)",
                            point.position
                        ),
                    )
                } else {
                    None
                }
            }
            (Setup::Taylor(spec), "final_length") => {
                (!(point.value > 0.0 && at_most(point, spec.length))).then(|| Implausible {
                    index,
                    column: "value",
                    message: format!(
                        "a final length of {} m: a Taylor rod shortens from its {} m (and stays \
                     longer than 0)",
                        point.value, spec.length
                    ),
                })
            }
            (Setup::Taylor(spec), "footprint_diameter" | "diameter") => {
                if !at_least(point, spec.diameter) {
                    refuse(
                        index,
                        "value",
                        format!(
                            "a {} of {} m is narrower than the rod's {} m: a compressed rod only \
                             widens (a radius given for a diameter?)",
                            point.quantity.replace('_', " "),
                            point.value,
                            spec.diameter
                        ),
                    )
                } else if point.quantity == "diameter" {
                    inside(
                        index,
                        point,
                        spec.length,
                        "a station (m from the impact face) of",
                    )
                } else {
                    None
                }
            }
            (Setup::Penetration(_), "nose_depth") => (!at_least(point, 0.0)).then(|| Implausible {
                index,
                column: "value",
                message: format!("a nose depth of {} m is negative", point.value),
            }),
            (Setup::Penetration(spec), "rod_length") => {
                (!(point.value > 0.0 && at_most(point, spec.rod_length))).then(|| Implausible {
                    index,
                    column: "value",
                    message: format!(
                        "a rod length of {} m: an eroding rod shortens from its {} m",
                        point.value, spec.rod_length
                    ),
                })
            }
            (Setup::Penetration(spec), "residual_velocity") => {
                residual_velocity(index, point, spec.velocity)
            }
            (Setup::Penetration(spec), "residual_mass") => {
                let rod = spec.rod.as_ref().map(|rod| {
                    core::f64::consts::PI
                        * 0.25
                        * spec.rod_diameter
                        * spec.rod_diameter
                        * spec.rod_length
                        * stoss_kernel::PointModel::density(rod.as_ref())
                });
                residual_mass(index, point, rod)
            }
            (Setup::BallisticLimit(_) | Setup::Perforation(_), "residual_velocity") => {
                residual_velocity(index, point, point.position)
            }
            (Setup::BallisticLimit(spec) | Setup::Perforation(spec), "residual_mass") => {
                let mass = spec.projectile.as_ref().and_then(|projectile| {
                    super::perforation::projectile_mass(spec, projectile).ok()
                });
                residual_mass(index, point, mass)
            }
            (Setup::BallisticLimit(_) | Setup::Perforation(_), "ballistic_limit") => {
                (point.value <= 0.0).then(|| Implausible {
                    index,
                    column: "value",
                    message: format!("a ballistic limit of {} m/s is not positive", point.value),
                })
            }
            (Setup::BlastPlate(spec), "deflection") => inside(
                index,
                point,
                spec.exposed_radius,
                "a radius (m from the plate's centre) of",
            ),
            (Setup::DropWeightBeam(spec), "first_crack_time") => {
                (!(at_least(point, 0.0) && at_most(point, spec.end_time))).then(|| Implausible {
                    index,
                    column: "value",
                    message: format!(
                        "a first crack time of {} s is outside the simulated 0..={} s (a time in \
                     ms read as s?)",
                        point.value, spec.end_time
                    ),
                })
            }
            (Setup::DropWeightBeam(spec), _) => {
                inside(index, point, spec.end_time, "a time (s after impact) of")
            }
            _ => None,
        };
        if found.is_some() {
            return found;
        }
    }
    match setup {
        Setup::Taylor(_) => {
            single(recording, "final_length").or_else(|| single(recording, "footprint_diameter"))
        }
        Setup::Penetration(_) => monotone(recording, "nose_depth", true)
            .or_else(|| monotone(recording, "rod_length", false)),
        _ => None,
    }
}

/// A residual velocity: not negative, not above the striking `velocity` (within the noise).
fn residual_velocity(index: usize, point: &RecordedPoint, velocity: f64) -> Option<Implausible> {
    (!(at_least(point, 0.0) && at_most(point, velocity))).then(|| Implausible {
        index,
        column: "value",
        message: format!(
            "a residual velocity of {} m/s: it lies between 0 and the striking {} m/s",
            point.value, velocity
        ),
    })
}

/// A residual mass: not negative, not above the projectile's `mass` when it is known.
fn residual_mass(index: usize, point: &RecordedPoint, mass: Option<f64>) -> Option<Implausible> {
    let bound = mass.unwrap_or(f64::INFINITY);
    (!(at_least(point, 0.0) && at_most(point, bound))).then(|| Implausible {
        index,
        column: "value",
        message: match mass {
            Some(mass) => format!(
                "a residual mass of {} kg: it lies between 0 and the projectile's {mass:.4e} kg",
                point.value
            ),
            None => format!("a residual mass of {} kg is negative", point.value),
        },
    })
}
