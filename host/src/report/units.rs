//! The units a report shows each measured quantity in: stresses in MPa, lengths in mm, times
//! in µs, velocities in m/s (recordings and predictions stay SI everywhere else).

/// How one quantity's values and positions are shown: `(axis label, factor from SI)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisplayUnits {
    /// The value axis.
    pub value: (&'static str, f64),
    /// The position axis.
    pub position: (&'static str, f64),
}

/// The display units of `quantity` (the experiment kinds' `QUANTITIES`); an unknown one stays
/// SI.
pub fn display_units(quantity: &str) -> DisplayUnits {
    let units = |value, position| DisplayUnits { value, position };
    const STRAIN: (&str, f64) = ("strain (-)", 1.0);
    const MPA: (&str, f64) = ("stress (MPa)", 1e-6);
    const MM: (&str, f64) = ("length (mm)", 1e3);
    const US: (&str, f64) = ("time (us)", 1e6);
    const MS: (&str, f64) = ("time (ms)", 1e3);
    match quantity {
        "true_stress" | "peak_stress" => units(MPA, ("plastic strain (-)", 1.0)),
        "engineering_stress" => units(MPA, ("engineering strain (-)", 1.0)),
        "axial_stress" => units(MPA, STRAIN),
        "final_length" | "footprint_diameter" | "diameter" => {
            units(MM, ("axial position (mm)", 1e3))
        }
        "nose_depth" | "rod_length" => units(MM, US),
        "deflection" | "peak_deflection" => units(("deflection (mm)", 1e3), ("radius (mm)", 1e3)),
        "residual_velocity" | "ballistic_limit" => {
            units(("velocity (m/s)", 1.0), ("impact velocity (m/s)", 1.0))
        }
        "residual_mass" => units(("mass (g)", 1e3), ("impact velocity (m/s)", 1.0)),
        "striker_displacement" => units(("displacement (mm)", 1e3), MS),
        "striker_velocity" => units(("velocity (m/s)", 1.0), MS),
        "beam_acceleration" => units(("acceleration (m/s^2)", 1.0), MS),
        "rebar_strain_midspan" | "rebar_strain_200mm" => units(("strain (%)", 1e2), MS),
        "first_crack_time" => units(MS, ("-", 1.0)),
        _ => units(("value (SI)", 1.0), ("position (SI)", 1.0)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::units::{recorded_dimensions, Dimension};

    #[test]
    fn every_experiment_quantity_has_display_units() {
        // GOAL: no quantity of any experiment kind is shown in raw SI by accident.
        // SETUP: every kind's QUANTITIES list.
        // REFERENCE: each maps to a unit other than the SI fallback; stresses in MPa.
        let kinds = crate::experiment::QUANTITIES_OF_EVERY_KIND;
        for quantity in kinds.iter().flat_map(|k| k.iter()) {
            let units = display_units(quantity);
            assert_ne!(units.value.0, "value (SI)", "{quantity}");
            if quantity.ends_with("_stress") {
                assert_eq!(units.value, ("stress (MPa)", 1e-6), "{quantity}");
            }
        }
    }

    #[test]
    fn recorded_quantities_agree_with_their_display_units() {
        // GOAL: the dimensions of recorded quantities (input) and the report's display units
        //   (output) describe the same quantities. SETUP: every experiment kind's QUANTITIES.
        // REFERENCE: lengths are shown in mm (factor 1e3), stresses in MPa (1e-6).
        let kinds = crate::experiment::QUANTITIES_OF_EVERY_KIND;
        for quantity in kinds.iter().flat_map(|k| k.iter()) {
            let (_, value) = recorded_dimensions(quantity).unwrap_or_else(|| panic!("{quantity}"));
            let shown = display_units(quantity).value.1;
            match value {
                Dimension::Length => assert_eq!(shown, 1e3, "{quantity}"),
                Dimension::Stress => assert_eq!(shown, 1e-6, "{quantity}"),
                _ => {}
            }
        }
    }
}
