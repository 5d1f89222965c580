//! Concrete perforation (seed 001 sec. 4; the October 1999 DERA/FOA/FFI/TNO benchmark): a
//! 152 mm ogive-nosed steel projectile perforates a plain high-strength concrete slab; the
//! exit velocity is recorded.
//!
//! The kind shares the ballistic kind's set-up and protocol ([`BallisticLimitSpec`]: the
//! projectile and slab of [`super::PenetrationSpec`], eroding contact with the eroded mass
//! kept, a shot decided once the projectile's shoulder has cleared the slab's main body), and
//! its quantities (`residual_velocity` and `residual_mass` at an impact velocity,
//! `ballistic_limit`). What differs:
//! - the slab is the calibrated part and must be **RHT concrete** ([`stoss_kernel::rht`]);
//! - beside the FE exit velocities `stoss simulate` prints the concrete cross-checks of
//!   [`crate::analytic::concrete`] for each recorded shot: Forrestal's semi-infinite depth and
//!   the modified NDRC perforation thickness, ballistic limit and Recht–Ipson exit velocity;
//! - the projectile velocity histories (the radar record) are charted and written, and the
//!   rear-face damage-zone diameter is reported.
//!
//! The bundled projectile is rigid (`projectile_rigid = true`, LS-DYNA `*MAT_RIGID`: seed 001
//! reports no projectile deformation, and Forrestal's and the NDRC models assume a rigid
//! one); its material file gives its density. Without the flag it is the file's material
//! (there, elastic steel: a J2 material whose yield stress lies far above any stress of the
//! shot).

use super::ballistic::BallisticLimitSpec;
use super::{FieldOutput, Outcome, SimulationError};
use crate::analytic::concrete::{forrestal, modified_ndrc, ndrc_ogive_nose_factor, ConcreteShot};
use crate::experiment::SummaryValue;
use crate::input::recording::RecordedPoint;
use crate::solver::SolverSettings;
use std::f64::consts::PI;
use std::fmt::Write as _;
use stoss_kernel::{PartMaterial, PointModel};

/// Quantities a perforation experiment records (those of the ballistic kind).
pub const QUANTITIES: &[&str] = super::ballistic::QUANTITIES;

/// The projectile's mass (kg) from its mesh (the blunted profile as meshed) and density;
/// `Err` if its nose cannot be meshed.
pub fn projectile_mass(
    spec: &BallisticLimitSpec,
    projectile: &PartMaterial,
) -> Result<f64, String> {
    let shot = spec.shot(1.0);
    let built = shot
        .model(projectile, projectile, &SolverSettings::default())
        .map_err(|error| error.to_string())?;
    let mesh = &built.model.mesh;
    Ok(built
        .rod_elements
        .iter()
        .map(|&e| {
            let mean_radius = 0.25
                * mesh.elements[e]
                    .iter()
                    .map(|&n| mesh.nodes[n][0])
                    .sum::<f64>();
            2.0 * PI * mean_radius * mesh.area(e) * projectile.density()
        })
        .sum())
}

/// Diameter of the rear-face damage zone (m): twice the largest reference radius of a live
/// slab element (part 0) with damage 1 in the slab's rear row of elements (its reference
/// centroid within one `element_size` of the rear face). FOI reports about 0.8 m for its
/// Autodyn runs with table 4.4's damage constants (seed 001 sec. 4.3).
pub fn rear_damage_diameter(spec: &BallisticLimitSpec, field: &FieldOutput) -> f64 {
    let mesh = &field.mesh;
    let centroid = |e: usize, d: usize| {
        0.25 * mesh.elements[e]
            .iter()
            .map(|&n| mesh.nodes[n][d])
            .sum::<f64>()
    };
    (0..mesh.elements.len())
        .filter(|&e| mesh.element_part[e] == 0 && !field.eroded[e])
        .filter(|&e| field.states[e].damage >= 1.0)
        .filter(|&e| centroid(e, 1) < -spec.plate_thickness + spec.element_size)
        .map(|e| 2.0 * centroid(e, 0))
        .fold(0.0, f64::max)
}

/// The analytic shot of `spec` against `target`, at `velocity` 0 (set it per shot), or why
/// there is none (the cross-checks need a tangent-ogive nose and RHT concrete). The mass is
/// the meshed projectile's ([`projectile_mass`]), computed once here.
pub fn concrete_shot(
    spec: &BallisticLimitSpec,
    target: &PartMaterial,
) -> Result<ConcreteShot, String> {
    let concrete = target
        .rht()
        .ok_or_else(|| format!("the target is {}, not RHT concrete", target.family()))?;
    let projectile = spec.projectile.as_deref().ok_or_else(|| {
        format!(
            "the projectile `{}` was not loaded",
            spec.projectile_material
        )
    })?;
    if spec.nose != super::penetration::Nose::Ogive {
        return Err("the cross-checks are for a tangent-ogive nose".into());
    }
    let radius = 0.5 * spec.projectile_diameter;
    let nose = spec.shot(1.0).nose_length();
    let ogive_radius = (nose * nose + radius * radius) / (2.0 * radius);
    Ok(ConcreteShot {
        mass: projectile_mass(spec, projectile)?,
        diameter: spec.projectile_diameter,
        caliber_radius_head: ogive_radius / spec.projectile_diameter,
        velocity: 0.0,
        compressive_strength: concrete.parameters.compressive_strength,
        density: concrete.density,
    })
}

/// Run the recorded shots ([`BallisticLimitSpec`]'s protocol) into RHT concrete and add the
/// concrete cross-checks to the report and the summary.
pub(super) fn simulate(
    spec: &BallisticLimitSpec,
    material: &PartMaterial,
    settings: &SolverSettings,
    recording: &[RecordedPoint],
) -> Result<Outcome, SimulationError> {
    let mut outcome = spec.simulate(material, settings, recording)?;
    let mut velocities: Vec<f64> = recording
        .iter()
        .filter(|p| p.quantity == "residual_velocity")
        .map(|p| p.position)
        .collect();
    velocities.sort_by(f64::total_cmp);
    velocities.dedup();
    let mut text = String::from(
        "\nanalytic cross-checks (rigid projectile; Forrestal: semi-infinite target; modified \
         NDRC with Recht-Ipson a = 1, p = 2)\n",
    );
    let _ = writeln!(
        text,
        "{:>10} {:>10} {:>14} {:>13} {:>13} {:>12} {:>12}",
        "Vi (m/s)", "FE Vr", "Forrestal P", "NDRC x", "NDRC e", "NDRC V_bl", "NDRC Vr"
    );
    let base = concrete_shot(spec, material);
    for &velocity in &velocities {
        let fe = recording
            .iter()
            .zip(&outcome.predicted)
            .find(|(p, _)| p.quantity == "residual_velocity" && p.position == velocity)
            .map_or(f64::NAN, |(_, &v)| v);
        let shot = match &base {
            Ok(base) => ConcreteShot { velocity, ..*base },
            Err(reason) => {
                let _ = writeln!(text, "{velocity:>10.1} not available: {reason}");
                continue;
            }
        };
        let depth = forrestal(&shot).map_or(f64::NAN, |f| f.depth);
        let nose = ndrc_ogive_nose_factor(shot.caliber_radius_head);
        match modified_ndrc(&shot, spec.plate_thickness, nose) {
            Ok(ndrc) => {
                let _ = writeln!(
                    text,
                    "{:>10.1} {:>10.1} {:>12.3} m {:>11.3} m {:>11.3} m {:>8.1} m/s {:>8.1} m/s",
                    velocity,
                    fe,
                    depth,
                    ndrc.depth,
                    ndrc.perforation_thickness,
                    ndrc.ballistic_limit,
                    ndrc.residual_velocity
                );
                outcome.summary.extend([
                    SummaryValue::new(format!("forrestal_depth_{velocity}"), depth, "m"),
                    SummaryValue::new(
                        format!("ndrc_perforation_thickness_{velocity}"),
                        ndrc.perforation_thickness,
                        "m",
                    ),
                    SummaryValue::new(
                        format!("ndrc_ballistic_limit_{velocity}"),
                        ndrc.ballistic_limit,
                        "m/s",
                    ),
                    SummaryValue::new(
                        format!("ndrc_residual_velocity_{velocity}"),
                        ndrc.residual_velocity,
                        "m/s",
                    ),
                ]);
            }
            Err(reason) => {
                let _ = writeln!(text, "{velocity:>10.1} NDRC not available: {reason}");
            }
        }
    }
    let meshed = match (&base, spec.projectile.as_deref()) {
        (Ok(base), _) => Some((base.mass, base.caliber_radius_head)),
        (Err(_), Some(projectile)) => projectile_mass(spec, projectile)
            .ok()
            .map(|mass| (mass, f64::NAN)),
        (Err(_), None) => None,
    };
    if let Some((mass, caliber_radius_head)) = meshed {
        let _ = writeln!(
            text,
            "slab {:.3} m; projectile {mass:.2} kg as meshed, CRH {caliber_radius_head:.2}",
            spec.plate_thickness
        );
        outcome
            .summary
            .push(SummaryValue::new("projectile_mass", mass, "kg"));
    }
    if let Some(field) = &outcome.field {
        let diameter = rear_damage_diameter(spec, field);
        let _ = writeln!(
            text,
            "rear-face damage zone (D = 1) of the shot in final.vtu: {diameter:.2} m in diameter"
        );
        outcome
            .summary
            .push(SummaryValue::new("rear_damage_diameter", diameter, "m"));
    }
    let report = outcome.report.get_or_insert_with(Default::default);
    report.text.push_str(&text);
    Ok(outcome)
}
