//! The unit system and the ids a card is written in.
//!
//! Explicit codes take no units: a model is consistent in a system of its own, chosen by the
//! sizes of one unit of mass, length and time (LS-DYNA's manual lists kg-m-s, kg-mm-ms with
//! GPa, t-mm-s with MPa, g-mm-ms with MPa, g-cm-us with Mbar...). A card's numbers are the
//! calibrated SI values divided by the SI size of their unit in that system
//! ([`CardUnits::from_si`]); temperatures stay in kelvin and dimensionless constants as they
//! are.

use std::fmt;

/// What a card field measures, for its conversion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// A ratio, an exponent, a flag, an id, or a temperature (kelvin in every system).
    Unchanged,
    /// Mass per volume.
    Density,
    /// Stress, pressure, modulus, energy per volume.
    Stress,
    /// Length over time.
    Velocity,
    /// Energy per mass and kelvin (J/kg/K = m^2/s^2/K).
    SpecificHeat,
    /// Energy per volume and kelvin (rho c_p).
    VolumetricHeat,
    /// One over time (a strain rate).
    Rate,
    /// Time.
    Time,
}

/// A consistent unit system: the SI size of one unit of mass, length and time, and their
/// names.
#[derive(Clone, Debug, PartialEq)]
pub struct CardUnits {
    /// Mass unit: its name and its size in kg.
    pub mass: (&'static str, f64),
    /// Length unit: its name and its size in m.
    pub length: (&'static str, f64),
    /// Time unit: its name and its size in s.
    pub time: (&'static str, f64),
}

const MASSES: [(&str, f64); 5] = [
    ("kg", 1.0),
    ("g", 1e-3),
    ("mg", 1e-6),
    ("t", 1e3),
    ("lbf-s2/in", 175.126_835_246_476_8),
];
const LENGTHS: [(&str, f64); 4] = [("m", 1.0), ("cm", 1e-2), ("mm", 1e-3), ("in", 0.0254)];
const TIMES: [(&str, f64); 4] = [("s", 1.0), ("ms", 1e-3), ("us", 1e-6), ("ns", 1e-9)];
/// Stress units a system's name may end with, for the check that it is the derived one.
const STRESSES: [(&str, f64); 8] = [
    ("Pa", 1.0),
    ("kPa", 1e3),
    ("MPa", 1e6),
    ("GPa", 1e9),
    ("TPa", 1e12),
    ("Mbar", 1e11),
    ("bar", 1e5),
    ("psi", 6_894.757_293_168_361),
];

impl Default for CardUnits {
    fn default() -> Self {
        Self::si()
    }
}

impl CardUnits {
    /// kg, m, s (stress in Pa).
    pub fn si() -> Self {
        Self {
            mass: MASSES[0],
            length: LENGTHS[0],
            time: TIMES[0],
        }
    }

    /// Whether this is kg-m-s.
    pub fn is_si(&self) -> bool {
        self.mass.1 == 1.0 && self.length.1 == 1.0 && self.time.1 == 1.0
    }

    /// Read a system from `si` or `<length>-<time>-<mass>[-<stress>]` in any order of the
    /// three base units (`mm-ms-kg-GPa`, `mm-s-t-MPa`, `mm-ms-g-MPa`, `cm-us-g-Mbar`,
    /// `in-s-lbf-s2/in-psi`); a stress unit, if given, must be the one the three imply.
    pub fn parse(text: &str) -> Result<Self, String> {
        let known = "si, or length-time-mass[-stress] with length m, cm, mm or in, time s, \
                     ms, us or ns, mass kg, g, mg, t or lbf-s2/in (e.g. mm-ms-kg-GPa, \
                     mm-s-t-MPa, mm-ms-g-MPa, cm-us-g-Mbar)";
        let trimmed = text.trim();
        if trimmed.eq_ignore_ascii_case("si") {
            return Ok(Self::si());
        }
        // `lbf-s2/in` holds a hyphen of its own.
        let spaced = trimmed.replace("lbf-s2/in", "lbf_s2/in");
        let parts: Vec<String> = spaced
            .split('-')
            .map(|p| p.replace("lbf_s2/in", "lbf-s2/in"))
            .collect();
        if !(3..=4).contains(&parts.len()) {
            return Err(format!("unit system `{text}`: expected {known}"));
        }
        let find = |table: &[(&'static str, f64)], name: &str| {
            table.iter().copied().find(|(n, _)| *n == name)
        };
        let (mut mass, mut length, mut time) = (None, None, None);
        for part in &parts[..3] {
            let part = part.as_str();
            match (
                find(&LENGTHS, part),
                find(&TIMES, part),
                find(&MASSES, part),
            ) {
                (Some(l), None, None) if length.is_none() => length = Some(l),
                (None, Some(t), None) if time.is_none() => time = Some(t),
                (None, None, Some(m)) if mass.is_none() => mass = Some(m),
                _ => return Err(format!("unit system `{text}`: `{part}`: expected {known}")),
            }
        }
        let (Some(mass), Some(length), Some(time)) = (mass, length, time) else {
            return Err(format!("unit system `{text}`: expected {known}"));
        };
        let units = Self { mass, length, time };
        if let Some(stress) = parts.get(3) {
            let Some((_, size)) = find(&STRESSES, stress) else {
                return Err(format!(
                    "unit system `{text}`: stress unit `{stress}` is not one of Pa, kPa, MPa, \
                     GPa, TPa, Mbar, bar, psi"
                ));
            };
            let derived = units.size(Quantity::Stress);
            if (size / derived - 1.0).abs() > 1e-9 {
                return Err(format!(
                    "unit system `{text}`: {}, {}, {} make the stress unit {}, not {stress}",
                    units.mass.0,
                    units.length.0,
                    units.time.0,
                    units.stress_name()
                ));
            }
        }
        Ok(units)
    }

    /// The SI size of one unit of `quantity` in this system.
    pub fn size(&self, quantity: Quantity) -> f64 {
        let (m, l, t) = (self.mass.1, self.length.1, self.time.1);
        match quantity {
            Quantity::Unchanged => 1.0,
            Quantity::Density => m / (l * l * l),
            Quantity::Stress => m / (l * t * t),
            Quantity::Velocity => l / t,
            Quantity::SpecificHeat => l * l / (t * t),
            Quantity::VolumetricHeat => m / (l * t * t),
            Quantity::Rate => 1.0 / t,
            Quantity::Time => t,
        }
    }

    /// `value` (SI) in this system.
    pub fn from_si(&self, value: f64, quantity: Quantity) -> f64 {
        value / self.size(quantity)
    }

    /// `value` in this system, in SI.
    pub fn to_si(&self, value: f64, quantity: Quantity) -> f64 {
        value * self.size(quantity)
    }

    /// The stress unit's name (a named one where the size matches, else its SI size).
    pub fn stress_name(&self) -> String {
        let size = self.size(Quantity::Stress);
        STRESSES
            .iter()
            .find(|(_, s)| (size / s - 1.0).abs() < 1e-9)
            .map_or_else(|| format!("{size:e} Pa"), |(n, _)| n.to_string())
    }

    /// The header line of a card: `mass kg, length mm, time ms, stress GPa, temperature K`.
    pub fn header(&self) -> String {
        format!(
            "units: mass {}, length {}, time {}, stress {}, temperature K",
            self.mass.0,
            self.length.0,
            self.time.0,
            self.stress_name()
        )
    }
}

impl fmt::Display for CardUnits {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_si() {
            write!(f, "si")
        } else {
            write!(
                f,
                "{}-{}-{}-{}",
                self.length.0,
                self.time.0,
                self.mass.0,
                self.stress_name()
            )
        }
    }
}

/// How the cards are written: the unit system, the material id and the material name.
#[derive(Clone, Debug, PartialEq)]
pub struct CardOptions {
    /// The unit system.
    pub units: CardUnits,
    /// The material id (LS-DYNA MID, OpenRadioss mat_ID; the EoS takes the same id).
    pub material_id: u32,
    /// The material name (Abaqus `NAME=`, OpenRadioss title).
    pub name: String,
}

impl Default for CardOptions {
    fn default() -> Self {
        Self {
            units: CardUnits::si(),
            material_id: 1,
            name: "STOSS".into(),
        }
    }
}

/// Largest material id a 10-column field holds with its separating blank.
pub const MAXIMUM_MATERIAL_ID: u32 = 99_999_999;

impl CardOptions {
    /// The options, checked: an id in 1..=[`MAXIMUM_MATERIAL_ID`], a name Abaqus accepts
    /// (a letter first, then letters, digits, `_` or `-`, at most 80 characters).
    pub fn new(units: CardUnits, material_id: u32, name: &str) -> Result<Self, String> {
        if !(1..=MAXIMUM_MATERIAL_ID).contains(&material_id) {
            return Err(format!(
                "--material-id {material_id}: must be in 1..={MAXIMUM_MATERIAL_ID} (it fills \
                 a 10-column card field)"
            ));
        }
        let valid = name.len() <= 80
            && name.starts_with(|c: char| c.is_ascii_alphabetic())
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        if !valid {
            return Err(format!(
                "--name `{name}`: a card name starts with a letter and holds only letters, \
                 digits, `_` and `-` (at most 80 characters; Abaqus' NAME= rule)"
            ));
        }
        Ok(Self {
            units,
            material_id,
            name: name.to_string(),
        })
    }
}

/// The systems the card tests write in (SI and four of LS-DYNA's), each with id 42 and name
/// `HHA`: `(system name, options)`.
#[cfg(test)]
pub(crate) fn test_systems() -> Vec<(&'static str, CardOptions)> {
    [
        "si",
        "mm-ms-kg-GPa",
        "mm-s-t-MPa",
        "mm-ms-g-MPa",
        "cm-us-g-Mbar",
    ]
    .into_iter()
    .map(|name| {
        let units = CardUnits::parse(name).expect("a known system");
        (
            name,
            CardOptions::new(units, 42, "HHA").expect("valid options"),
        )
    })
    .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_named_systems_give_the_stress_units_their_users_know() {
        // GOAL: a unit system is read from the name LS-DYNA users give it, and its derived
        //       units are the manual's.
        // SETUP: the systems of LS-DYNA's unit table.
        // REFERENCE: LS-DYNA's consistent-units table: kg-mm-ms: GPa, steel 7.83e-6 kg/mm^3;
        //            t-mm-s: MPa, 7.83e-9 t/mm^3, c_p 4.77e8 mm^2/s^2/K; g-mm-ms: MPa;
        //            g-cm-us: Mbar; a wrong stress suffix is refused.
        for (name, stress) in [
            ("mm-ms-kg-GPa", "GPa"),
            ("mm-s-t-MPa", "MPa"),
            ("mm-ms-g-MPa", "MPa"),
            ("cm-us-g-Mbar", "Mbar"),
            ("kg-m-s", "Pa"),
            ("in-s-lbf-s2/in-psi", "psi"),
            ("si", "Pa"),
        ] {
            let units = CardUnits::parse(name).unwrap();
            assert_eq!(units.stress_name(), stress, "{name}");
        }
        let units = CardUnits::parse("mm-ms-kg").unwrap();
        assert!((units.from_si(7830.0, Quantity::Density) - 7.83e-6).abs() < 1e-18);
        assert!((units.from_si(792e6, Quantity::Stress) - 0.792).abs() < 1e-15);
        assert!((units.from_si(1.0, Quantity::Rate) - 1e-3).abs() < 1e-18);
        // J/(kg K) = mm^2/ms^2/K: the same number; in t-mm-s it is mm^2/s^2/K, 1e6 times more.
        assert!((units.from_si(477.0, Quantity::SpecificHeat) - 477.0).abs() < 1e-12);
        let tonne = CardUnits::parse("mm-s-t-MPa").unwrap();
        assert!((tonne.from_si(477.0, Quantity::SpecificHeat) / 4.77e8 - 1.0).abs() < 1e-14);
        assert!((tonne.from_si(7830.0, Quantity::Density) / 7.83e-9 - 1.0).abs() < 1e-14);
        assert!((units.from_si(5000.0, Quantity::Velocity) - 5000.0).abs() < 1e-9);
        assert!((tonne.from_si(5000.0, Quantity::Velocity) / 5.0e6 - 1.0).abs() < 1e-14);
        let error = CardUnits::parse("mm-ms-kg-MPa").unwrap_err();
        assert!(error.contains("make the stress unit GPa"), "{error}");
        assert!(CardUnits::parse("mm-ms").is_err());
        assert!(CardUnits::parse("mm-mm-kg").is_err());
        assert!(CardOptions::new(CardUnits::si(), 0, "STEEL").is_err());
        assert!(CardOptions::new(CardUnits::si(), 7, "4340").is_err());
        assert!(CardOptions::new(CardUnits::si(), 7, "HHA_steel-2").is_ok());
    }
}
