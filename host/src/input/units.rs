//! Units of input quantities: one table of the unit symbols stoss reads, their dimension and
//! their factor to SI, and the dimension each input field and each recorded quantity has.
//! Everything is converted to SI on load; the rest of stoss sees SI only.
//!
//! A small table rather than a units crate: stoss needs to *parse* a unit written by a user
//! (`"25.4 mm"`, a CSV header `value [MPa]`), check it against the field's dimension and scale
//! it once. Compile-time dimension types (`uom`, `dimensioned`) do not parse strings, and the
//! parsing crates seen (`units-of-measure`-style registries) carry far more than the dozen
//! dimensions of impact mechanics. The table below is the one home of every unit symbol.
//! A model constant's dimension comes from its unit in the kernel's descriptor; the name rules
//! of [`field_dimension`] cover the set-up, campaign and recording fields.

use stoss_kernel::parameters::Parameter;

/// The physical dimension of a quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// A pure number (strain, ratios, exponents).
    Dimensionless,
    /// m.
    Length,
    /// s.
    Time,
    /// m/s.
    Velocity,
    /// m/s^2.
    Acceleration,
    /// Pa.
    Stress,
    /// kg/m^3.
    Density,
    /// K (absolute).
    Temperature,
    /// kg.
    Mass,
    /// J.
    Energy,
    /// 1/s.
    StrainRate,
    /// J/(kg K).
    SpecificHeat,
}

impl Dimension {
    /// The SI unit's symbol.
    pub fn si_unit(self) -> &'static str {
        match self {
            Dimension::Dimensionless => "1",
            Dimension::Length => "m",
            Dimension::Time => "s",
            Dimension::Velocity => "m/s",
            Dimension::Acceleration => "m/s^2",
            Dimension::Stress => "Pa",
            Dimension::Density => "kg/m^3",
            Dimension::Temperature => "K",
            Dimension::Mass => "kg",
            Dimension::Energy => "J",
            Dimension::StrainRate => "1/s",
            Dimension::SpecificHeat => "J/(kg K)",
        }
    }

    /// A name for messages.
    pub fn name(self) -> &'static str {
        match self {
            Dimension::Dimensionless => "a pure number",
            Dimension::Length => "a length",
            Dimension::Time => "a time",
            Dimension::Velocity => "a velocity",
            Dimension::Acceleration => "an acceleration",
            Dimension::Stress => "a stress",
            Dimension::Density => "a density",
            Dimension::Temperature => "a temperature",
            Dimension::Mass => "a mass",
            Dimension::Energy => "an energy",
            Dimension::StrainRate => "a strain rate",
            Dimension::SpecificHeat => "a specific heat",
        }
    }
}

/// A unit: its dimension and `SI = factor * x + offset` (the offset only for °C).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unit {
    /// Its dimension.
    pub dimension: Dimension,
    /// Factor to SI.
    pub factor: f64,
    /// Offset to SI (absolute temperatures in °C).
    pub offset: f64,
}

/// `10^k` for the factors that are powers of ten (`None` otherwise).
fn decimal_exponent(factor: f64) -> Option<i32> {
    (-12..=12).find(|&k| {
        let power = format!("1e{k}").parse::<f64>().unwrap_or(f64::NAN);
        power == factor
    })
}

/// The decimal number `number` times `10^exponent`, rounded once: `("812", 6)` is parsed as
/// `812e6`, so a value given with a decimal unit (MPa, mm, %) is the same double as the same
/// value typed in SI.
fn shifted_decimal(number: &str, exponent: i32) -> Option<f64> {
    let (mantissa, own) = match number.find(['e', 'E']) {
        Some(at) => (&number[..at], number[at + 1..].parse::<i32>().ok()?),
        None => (number, 0),
    };
    format!("{mantissa}e{}", own.checked_add(exponent)?)
        .parse()
        .ok()
}

impl Unit {
    /// An absolute value in this unit, in SI.
    pub fn to_si(self, value: f64) -> f64 {
        self.factor * value + self.offset
    }

    /// The number written `text` in this unit, in SI; a decimal unit shifts the decimal
    /// exponent instead of multiplying, so that `812 MPa` is exactly `812e6`. `None` if `text`
    /// is not a number.
    pub fn parse_to_si(self, text: &str) -> Option<f64> {
        let text = text.trim();
        let value: f64 = text.parse().ok()?;
        if self.offset == 0.0 && value.is_finite() {
            if let Some(exponent) = decimal_exponent(self.factor) {
                return shifted_decimal(text, exponent);
            }
        }
        Some(self.to_si(value))
    }

    /// The number written `text`, a difference or uncertainty in this unit, in SI.
    pub fn parse_difference_to_si(self, text: &str) -> Option<f64> {
        Unit {
            offset: 0.0,
            ..self
        }
        .parse_to_si(text)
    }
}

/// Every unit symbol stoss reads: `(symbols, dimension, factor to SI)`.
const UNITS: &[(&[&str], Dimension, f64)] = &[
    (&["1", "-", ""], Dimension::Dimensionless, 1.0),
    (&["%"], Dimension::Dimensionless, 1e-2),
    (
        &["microstrain", "ue", "µε", "με"],
        Dimension::Dimensionless,
        1e-6,
    ),
    (&["m"], Dimension::Length, 1.0),
    (&["cm"], Dimension::Length, 1e-2),
    (&["mm"], Dimension::Length, 1e-3),
    (&["um", "µm", "μm"], Dimension::Length, 1e-6),
    (&["in", "inch"], Dimension::Length, 0.0254),
    (&["ft"], Dimension::Length, 0.3048),
    (&["s"], Dimension::Time, 1.0),
    (&["ms"], Dimension::Time, 1e-3),
    (&["us", "µs", "μs"], Dimension::Time, 1e-6),
    (&["ns"], Dimension::Time, 1e-9),
    (&["m/s"], Dimension::Velocity, 1.0),
    (&["km/s", "mm/us", "mm/µs"], Dimension::Velocity, 1e3),
    (&["ft/s"], Dimension::Velocity, 0.3048),
    (&["m/s^2", "m/s2"], Dimension::Acceleration, 1.0),
    // Standard gravity (CGPM 1901).
    (&["g_n"], Dimension::Acceleration, 9.80665),
    (&["Pa"], Dimension::Stress, 1.0),
    (&["kPa"], Dimension::Stress, 1e3),
    (&["MPa", "N/mm^2", "N/mm2"], Dimension::Stress, 1e6),
    (&["GPa"], Dimension::Stress, 1e9),
    (&["bar"], Dimension::Stress, 1e5),
    (&["psi"], Dimension::Stress, 6_894.757_293_168_361),
    (&["ksi"], Dimension::Stress, 6_894_757.293_168_361),
    (&["kg/m^3", "kg/m3"], Dimension::Density, 1.0),
    (&["g/cm^3", "g/cm3", "g/cc"], Dimension::Density, 1e3),
    (&["K"], Dimension::Temperature, 1.0),
    (&["kg"], Dimension::Mass, 1.0),
    (&["g"], Dimension::Mass, 1e-3),
    (&["mg"], Dimension::Mass, 1e-6),
    (&["J"], Dimension::Energy, 1.0),
    (&["kJ"], Dimension::Energy, 1e3),
    (&["MJ"], Dimension::Energy, 1e6),
    (&["1/s", "/s", "s^-1"], Dimension::StrainRate, 1.0),
    (
        &["J/(kg K)", "J/kg/K", "J/(kg*K)"],
        Dimension::SpecificHeat,
        1.0,
    ),
];

/// The unit written `symbol` (case-sensitive: `mm` is not `Mm`); °C (`degC`, `°C`, `C`) and
/// °F (`degF`, `°F`, `F`: `T = (F - 32) 5/9 + 273.15` K) are absolute temperatures (their
/// differences and uncertainties scale without the offset).
pub fn unit(symbol: &str) -> Option<Unit> {
    let symbol = symbol.trim();
    if matches!(symbol, "degC" | "°C" | "C") {
        return Some(Unit {
            dimension: Dimension::Temperature,
            factor: 1.0,
            offset: 273.15,
        });
    }
    if matches!(symbol, "degF" | "°F" | "F") {
        return Some(Unit {
            dimension: Dimension::Temperature,
            factor: 5.0 / 9.0,
            offset: 273.15 - 32.0 * 5.0 / 9.0,
        });
    }
    UNITS
        .iter()
        .find(|(symbols, _, _)| symbols.contains(&symbol))
        .map(|&(_, dimension, factor)| Unit {
            dimension,
            factor,
            offset: 0.0,
        })
}

/// Every unit symbol of `dimension`, for messages.
pub fn symbols_of(dimension: Dimension) -> Vec<&'static str> {
    let mut symbols: Vec<&'static str> = UNITS
        .iter()
        .filter(|(_, d, _)| *d == dimension)
        .flat_map(|(s, _, _)| s.iter().copied())
        .filter(|s| !s.is_empty())
        .collect();
    if dimension == Dimension::Temperature {
        symbols.push("degC");
        symbols.push("degF");
    }
    symbols
}

/// `"25.4 mm"` -> 0.0254 (SI) if it is a number followed by a unit of `expected`; `Ok(None)` if
/// `text` is not a number with a unit at all; an error if the unit is unknown or of another
/// dimension.
pub fn quantity_to_si(text: &str, expected: Dimension) -> Result<Option<f64>, String> {
    let text = text.trim();
    let split = text
        .char_indices()
        .find(|&(i, c)| {
            !(c.is_ascii_digit() || c == '.' || c == '+' || c == '-' || c == '_')
                && !((c == 'e' || c == 'E')
                    && text[i + 1..]
                        .chars()
                        .next()
                        .is_some_and(|n| n.is_ascii_digit() || n == '-' || n == '+'))
        })
        .map_or(text.len(), |(i, _)| i);
    let (number, symbol) = text.split_at(split);
    let number = number.replace('_', "");
    let Ok(value) = number.parse::<f64>() else {
        return Ok(None);
    };
    if !value.is_finite() {
        return Err(format!("{text:?} is not finite"));
    }
    let symbol = symbol.trim();
    let Some(unit) = unit(symbol) else {
        return Err(format!(
            "unknown unit {symbol:?} in {text:?}; {} takes {}",
            expected.name(),
            symbols_of(expected).join(", ")
        ));
    };
    if unit.dimension != expected {
        return Err(format!(
            "{text:?} is {}, but this field is {} ({})",
            unit.dimension.name(),
            expected.name(),
            symbols_of(expected).join(", ")
        ));
    }
    Ok(unit.parse_to_si(&number))
}

/// The dimension of an input field (a TOML key), from its name: `None` for a field that is
/// not a dimensioned quantity (names, kinds, pure-number constants). The suffix rules are the
/// project's naming convention for fields, so a new field follows them by its name.
pub fn field_dimension(key: &str) -> Option<Dimension> {
    let key = key.rsplit('.').next().unwrap_or(key).trim_matches('"');
    // A model constant has the dimension of its unit in the kernel's descriptor.
    described_dimension(key).unwrap_or_else(|| named_dimension(key))
}

/// The dimension a set-up, campaign or recording field's name gives (its suffix).
fn named_dimension(key: &str) -> Option<Dimension> {
    // A numbered field (`saturation_stress_1`) has the dimension of its name.
    let key = match key.rsplit_once('_') {
        Some((stem, number))
            if !number.is_empty() && number.bytes().all(|b| b.is_ascii_digit()) =>
        {
            stem
        }
        _ => key,
    };
    // Ratios and exponents are pure numbers whatever their names end in
    // (`shear_strength_ratio`, `tensile_rate_exponent`).
    if key.ends_with("_exponent") || key.ends_with("_ratio") {
        return None;
    }
    const RULES: &[(&[&str], Dimension)] = &[
        (
            &[
                "_stress",
                "_modulus",
                "pressure",
                "_strength",
                "yield_stress",
            ],
            Dimension::Stress,
        ),
        (
            &[
                "thickness",
                "radius",
                "diameter",
                "length",
                "_size",
                "standoff",
                "gap",
                "height",
                "width",
                "depth",
                "_gauge",
            ],
            Dimension::Length,
        ),
        (&["velocity", "speed"], Dimension::Velocity),
        (
            &["_time", "time", "interval", "duration", "damping_start"],
            Dimension::Time,
        ),
        (&["temperature"], Dimension::Temperature),
        (&["density"], Dimension::Density),
        (&["mass"], Dimension::Mass),
        (&["energy"], Dimension::Energy),
        (&["specific_heat"], Dimension::SpecificHeat),
        (&["strain_rate", "reference_rate"], Dimension::StrainRate),
    ];
    RULES
        .iter()
        .find(|(suffixes, _)| suffixes.iter().any(|s| key.ends_with(s)))
        .map(|&(_, dimension)| dimension)
}

/// Every described constant of the kernel's model families (strength laws and terms, EoS,
/// heating, RHT and K&C concrete), as [`stoss_kernel::parameters`] describes them.
pub fn described_constants() -> impl Iterator<Item = &'static Parameter> {
    use stoss_kernel::eos::{Jwl, LinearEos, MieGruneisen, PAlpha, Polynomial};
    use stoss_kernel::strength::{
        Hardening, JohnsonCook, KhanHuangLiang, MechanicalThresholdStress, ModifiedJohnsonCook,
        PrestonTonksWallace, RateTerm, ThermalTerm, TwoRateJohnsonCook, VoceKocks,
        ZerilliArmstrong,
    };
    let families: [&'static [Parameter]; 15] = [
        MechanicalThresholdStress::PARAMETERS,
        KhanHuangLiang::PARAMETERS,
        VoceKocks::PARAMETERS,
        JohnsonCook::PARAMETERS,
        ZerilliArmstrong::PARAMETERS,
        PrestonTonksWallace::PARAMETERS,
        ModifiedJohnsonCook::PARAMETERS,
        TwoRateJohnsonCook::PARAMETERS,
        stoss_kernel::rht::RhtParameters::PARAMETERS,
        stoss_kernel::kc::KcParameters::PARAMETERS,
        LinearEos::PARAMETERS,
        MieGruneisen::PARAMETERS,
        Polynomial::PARAMETERS,
        Jwl::PARAMETERS,
        PAlpha::PARAMETERS,
    ];
    families
        .into_iter()
        .chain(Hardening::VARIANT_PARAMETERS.iter().copied())
        .chain(RateTerm::VARIANT_PARAMETERS.iter().copied())
        .chain(ThermalTerm::VARIANT_PARAMETERS.iter().copied())
        .chain(stoss_kernel::Heating::VARIANT_PARAMETERS.iter().copied())
        .flatten()
}

/// The dimension of a kernel descriptor's SI unit; `None` for a pure number or a unit input
/// files have no dimension for (`1/K`, `1/Pa`: written as plain SI numbers). An energy per
/// volume (`J/m^3`) is a stress.
pub fn unit_dimension(unit: &str) -> Option<Dimension> {
    if unit == "J/m^3" {
        return Some(Dimension::Stress);
    }
    ALL_DIMENSIONS
        .into_iter()
        .filter(|dimension| *dimension != Dimension::Dimensionless)
        .find(|dimension| dimension.si_unit() == unit)
}

/// The dimension of the model constant named `name` from its descriptor: `Some(None)` for a
/// described pure number, `None` if no family describes a constant of that name.
fn described_dimension(name: &str) -> Option<Option<Dimension>> {
    described_constants()
        .find(|parameter| parameter.name == name)
        .map(|parameter| unit_dimension(parameter.unit))
}

const ALL_DIMENSIONS: [Dimension; 12] = [
    Dimension::Dimensionless,
    Dimension::Length,
    Dimension::Time,
    Dimension::Velocity,
    Dimension::Acceleration,
    Dimension::Stress,
    Dimension::Density,
    Dimension::Temperature,
    Dimension::Mass,
    Dimension::Energy,
    Dimension::StrainRate,
    Dimension::SpecificHeat,
];

/// The plausible range `(least, most)` of an input of `dimension` in SI, for the magnitude of
/// the value (0 is always accepted): beyond it a value is far more likely a unit slip (a rod
/// of 25.4 m, a yield stress of 1e20 Pa, a temperature of 20 K meant as °C) than an impact
/// experiment, and stoss refuses it unless `--force`. `None`: no range (pure numbers).
pub fn plausible_range(dimension: Dimension) -> Option<(f64, f64)> {
    Some(match dimension {
        Dimension::Dimensionless => return None,
        // Moduli and flow stresses: from soft polymers to diamond.
        Dimension::Stress => (1.0e3, 2.0e12),
        // From a micrometre-scale element to a 10 m structure.
        Dimension::Length => (1.0e-7, 10.0),
        // Up to orbital debris and detonation speeds.
        Dimension::Velocity => (1.0e-6, 1.0e4),
        // From a building's sway to a struck striker's shock.
        Dimension::Acceleration => (1.0e-6, 1.0e9),
        // From a nanosecond step to an hour of test time.
        Dimension::Time => (1.0e-12, 3600.0),
        Dimension::Temperature => (1.0, 1.0e4),
        // From air to the densest metals.
        Dimension::Density => (0.1, 1.0e5),
        Dimension::Mass => (1.0e-9, 1.0e5),
        Dimension::Energy => (1.0e-6, 1.0e12),
        Dimension::StrainRate => (1.0e-9, 1.0e9),
        Dimension::SpecificHeat => (10.0, 1.0e5),
    })
}

/// `(position, value)` dimensions of a recorded quantity (the experiment kinds' `QUANTITIES`);
/// `None` for a quantity stoss does not know.
pub fn recorded_dimensions(quantity: &str) -> Option<(Dimension, Dimension)> {
    use Dimension::*;
    Some(match quantity {
        "true_stress" | "peak_stress" | "engineering_stress" | "axial_stress" => {
            (Dimensionless, Stress)
        }
        "final_length" | "footprint_diameter" | "diameter" => (Length, Length),
        "nose_depth" | "rod_length" => (Time, Length),
        "deflection" | "peak_deflection" => (Length, Length),
        "residual_velocity" | "ballistic_limit" | "exit_velocity" => (Velocity, Velocity),
        "residual_mass" => (Velocity, Mass),
        "striker_displacement" => (Time, Length),
        "striker_velocity" => (Time, Velocity),
        "beam_acceleration" => (Time, Acceleration),
        "rebar_strain_midspan" | "rebar_strain_200mm" => (Time, Dimensionless),
        "first_crack_time" => (Dimensionless, Time),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantities_with_units_convert_to_si() {
        // GOAL: the units of impact-mechanics inputs convert exactly to SI.
        // SETUP: one value per dimension, in a non-SI unit.
        // REFERENCE: the definitions (1 in = 25.4 mm, 1 psi = 6894.757293168361 Pa, 0 °C =
        //   273.15 K, 1 g/cc = 1000 kg/m^3).
        let si = |text, dimension| quantity_to_si(text, dimension).unwrap().unwrap();
        assert_eq!(si("25.4 mm", Dimension::Length), 0.0254);
        assert_eq!(si("1 in", Dimension::Length), 0.0254);
        assert_eq!(si("130 m/s", Dimension::Velocity), 130.0);
        assert_eq!(si("1.7 km/s", Dimension::Velocity), 1700.0);
        assert_eq!(si("92 MPa", Dimension::Stress), 92.0e6);
        assert_eq!(
            si("1e3 psi", Dimension::Stress),
            1e3 * 6_894.757_293_168_361
        );
        assert_eq!(si("20 degC", Dimension::Temperature), 293.15);
        // 68 °F = 20 °C; 212 °F = 100 °C; a difference of 9 °F is 5 K.
        assert!((si("68 degF", Dimension::Temperature) - 293.15).abs() < 1e-12);
        assert!((si("212 °F", Dimension::Temperature) - 373.15).abs() < 1e-12);
        let fahrenheit = unit("degF").unwrap();
        assert!((fahrenheit.parse_difference_to_si("9").unwrap() - 5.0).abs() < 1e-14);
        assert_eq!(si("7.85 g/cc", Dimension::Density), 7850.0);
        assert_eq!(si("55 us", Dimension::Time), 55.0e-6);
        assert_eq!(si("37.5 g", Dimension::Mass), 0.0375);
        assert_eq!(si("2.5e-1%", Dimension::Dimensionless), 0.0025);
        assert_eq!(si("1e-3 /s", Dimension::StrainRate), 1e-3);
        assert_eq!(si("477 J/(kg K)", Dimension::SpecificHeat), 477.0);
        // Decimal units shift the exponent: the same double as the SI text.
        assert_eq!(si("0.3 %", Dimension::Dimensionless), 0.003);
        assert_eq!(si("0.1 mm", Dimension::Length), 0.1e-3);
        assert_eq!(si("1.2e-1 GPa", Dimension::Stress), 1.2e8);
        assert_eq!(si("2.3 us", Dimension::Time), 2.3e-6);
    }

    #[test]
    fn wrong_or_unknown_units_are_errors_and_words_are_not_quantities() {
        // GOAL: a length given in MPa, an unknown unit and a non-finite value are refused with
        //   the valid units; text that is not a number with a unit is left alone.
        // SETUP: the slips of issue 17. REFERENCE: the messages name the dimensions.
        let error = quantity_to_si("25.4 MPa", Dimension::Length).unwrap_err();
        assert!(
            error.contains("a stress") && error.contains("mm"),
            "{error}"
        );
        let error = quantity_to_si("3 furlongs", Dimension::Length).unwrap_err();
        assert!(error.contains("unknown unit"), "{error}");
        assert!(quantity_to_si("1e999 mm", Dimension::Length).is_err());
        assert_eq!(quantity_to_si("c4", Dimension::Length), Ok(None));
        assert_eq!(quantity_to_si("far-face", Dimension::Length), Ok(None));
    }

    #[test]
    fn every_dimensioned_field_has_a_range_around_the_bundled_values() {
        // GOAL: the plausibility ranges accept every bundled experiment, material and campaign
        //   (they are checked on load: a range that refused one would fail its tests) and
        //   refuse the unit slips of issue 17. SETUP: the slips. REFERENCE: outside the range.
        let outside = |value: f64, dimension| {
            let (least, most) = plausible_range(dimension).unwrap();
            !(value == 0.0 || (least..=most).contains(&value.abs()))
        };
        assert!(outside(25.4, Dimension::Length) && !outside(25.4e-3, Dimension::Length));
        assert!(outside(1e20, Dimension::Stress) && !outside(792e6, Dimension::Stress));
        assert!(outside(13_000.0, Dimension::Velocity) && !outside(1700.0, Dimension::Velocity));
        assert!(outside(0.5, Dimension::Temperature) && !outside(298.0, Dimension::Temperature));
        assert!(plausible_range(Dimension::Dimensionless).is_none());
    }

    #[test]
    fn model_constants_take_their_dimension_from_the_kernel_descriptor() {
        // GOAL: a model constant's dimension is its descriptor unit's, whatever its name, and
        //       one name means one unit in every family (else the reader could not tell).
        // SETUP: every described constant of every family.
        // REFERENCE: the descriptor units; ZA's C1 (Pa) and the rate term's upturn rate
        //            (1/s) have names no suffix rule recognises.
        for parameter in described_constants() {
            for other in described_constants().filter(|p| p.name == parameter.name) {
                assert_eq!(parameter.unit, other.unit, "{}", parameter.name);
            }
            assert_eq!(
                field_dimension(parameter.name),
                unit_dimension(parameter.unit),
                "{}",
                parameter.name
            );
        }
        assert_eq!(field_dimension("strength.c1"), Some(Dimension::Stress));
        assert_eq!(field_dimension("upturn_rate"), Some(Dimension::StrainRate));
        assert_eq!(
            field_dimension("detonation_energy"),
            Some(Dimension::Stress)
        );
        assert_eq!(field_dimension("saturation_rate_1"), None);
    }

    #[test]
    fn field_names_give_their_dimension() {
        // GOAL: the fields of the bundled files get the right dimension from their names.
        // SETUP: fields of materials, experiments and campaigns.
        // REFERENCE: their documented SI units.
        use Dimension::*;
        for (key, dimension) in [
            ("yield_stress", Some(Stress)),
            ("shear_modulus", Some(Stress)),
            ("rod_length", Some(Length)),
            ("standoff", Some(Length)),
            ("element_size", Some(Length)),
            ("velocity", Some(Velocity)),
            ("end_time", Some(Time)),
            ("output_interval", Some(Time)),
            ("melting_temperature", Some(Temperature)),
            ("density", Some(Density)),
            ("charge.mass", Some(Mass)),
            ("specific_heat", Some(SpecificHeat)),
            ("rate_sensitivity", None),
            ("saturation_stress_1", Some(Stress)),
            ("compressive_reference_rate", Some(StrainRate)),
            ("incident_gauge", Some(Length)),
            ("shear_strength_ratio", None),
            ("tensile_rate_exponent", None),
            ("erosion_geometric_strain", None),
            ("anvil_friction", None),
            ("recorded_scale", None),
            ("hardening_exponent", None),
            ("poissons_ratio", None),
            ("name", None),
            ("kind", None),
        ] {
            assert_eq!(field_dimension(key), dimension, "{key}");
        }
    }
}
