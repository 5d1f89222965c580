//! The history carried per integration point between steps.

use crate::tensor::{self, Sym};

/// Bit flags describing a point's condition after an update.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StateFlags(pub u32);

impl StateFlags {
    /// The point yielded in the last step.
    pub const PLASTIC: u32 = 1;
    /// Damage reached 1: the point carries no shear and no tension from now on.
    pub const FAILED: u32 = 2;
    /// The host should erode (delete) the element.
    pub const ERODE: u32 = 4;
    /// Pressure was held at the tensile cut-off in the last step.
    pub const PRESSURE_CUTOFF: u32 = 8;

    /// `true` if `flag` is set.
    #[inline]
    pub fn contains(self, flag: u32) -> bool {
        self.0 & flag != 0
    }

    /// Set `flag`.
    #[inline]
    pub fn insert(&mut self, flag: u32) {
        self.0 |= flag;
    }

    /// Clear `flag`.
    #[inline]
    pub fn remove(&mut self, flag: u32) {
        self.0 &= !flag;
    }
}

/// The yield check's flow stress `sigma_y(eps_p, 0, T)` (Pa), kept with the plastic strain
/// and temperature it was evaluated at. A step from a state with exactly that plastic strain
/// and temperature (every step after an elastic one, until the point yields or the host
/// changes either) checks yield against it without evaluating the strength model: the elastic
/// step of a JC point after flow calls no `pow`. It is the value the step would compute, so
/// results do not depend on whether it is present; a state without it ([`YieldCheck::NONE`],
/// e.g. read through the C ABI's batch entry, which does not carry it) evaluates the check.
/// A host never needs to write it: a state it assembles itself (rather than keeping one the
/// kernel returned) carries [`YieldCheck::NONE`], as [`MaterialState::initial`] does; a stored
/// value with matching keys is trusted, not re-evaluated.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct YieldCheck {
    /// `sigma_y(eps_p, 0, T)` (Pa).
    pub flow_stress: f64,
    /// The plastic strain it was evaluated at (-).
    pub plastic_strain: f64,
    /// The temperature it was evaluated at (K).
    pub temperature: f64,
}

impl YieldCheck {
    /// No stored check: its keys (-1) match no admissible state.
    pub const NONE: YieldCheck = YieldCheck {
        flow_stress: 0.0,
        plastic_strain: -1.0,
        temperature: -1.0,
    };

    /// The stored flow stress if it was evaluated at exactly this plastic strain and
    /// temperature.
    #[inline(always)]
    pub fn at(&self, plastic_strain: f64, temperature: f64) -> Option<f64> {
        ((self.plastic_strain == plastic_strain) & (self.temperature == temperature))
            .then_some(self.flow_stress)
    }
}

/// State of one integration point.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MaterialState {
    /// Cauchy stress (Pa), Voigt `xx yy zz xy yz zx`, tension positive.
    pub stress: Sym,
    /// Equivalent plastic strain `eps_p` (-).
    pub plastic_strain: f64,
    /// Equivalent plastic strain rate of the last step `deps_p` (1/s).
    pub plastic_strain_rate: f64,
    /// Temperature `T` (K).
    pub temperature: f64,
    /// Damage `D` in `[0, 1]`.
    pub damage: f64,
    /// Relative volume `V/V0 = rho0/rho`.
    pub relative_volume: f64,
    /// Internal energy per unit reference volume `E` (J/m^3).
    pub internal_energy: f64,
    /// Internal variable of a history-dependent EoS (e.g. P-alpha distension); 0 otherwise.
    pub eos_history: f64,
    /// Condition flags, see [`StateFlags`].
    pub flags: StateFlags,
    /// The last yield check evaluated, see [`YieldCheck`] (not a state variable: excluded from
    /// equality, finiteness and range checks).
    pub yield_check: YieldCheck,
}

/// Equal stored state variables and flags ([`MaterialState::yield_check`], a stored
/// evaluation, is not compared).
impl PartialEq for MaterialState {
    fn eq(&self, other: &Self) -> bool {
        self.stress == other.stress
            && self.plastic_strain == other.plastic_strain
            && self.plastic_strain_rate == other.plastic_strain_rate
            && self.temperature == other.temperature
            && self.damage == other.damage
            && self.relative_volume == other.relative_volume
            && self.internal_energy == other.internal_energy
            && self.eos_history == other.eos_history
            && self.flags == other.flags
    }
}

/// Description of a state variable a host carries between steps: its name (as in
/// [`MaterialState`]), unit and valid range. A state outside it is impossible for any model
/// (a host wrote it, not the kernel) and is refused before an update.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StateVariable {
    /// Field name in [`MaterialState`].
    pub name: &'static str,
    /// SI unit.
    pub unit: &'static str,
    /// Lower bound.
    pub lower: f64,
    /// `true` if the lower bound itself is excluded.
    pub lower_excluded: bool,
    /// Upper bound (inclusive; `+inf` for none).
    pub upper: f64,
}

impl StateVariable {
    /// `true` if `value` is in the valid range.
    #[inline]
    pub fn admits(&self, value: f64) -> bool {
        let above = if self.lower_excluded {
            value > self.lower
        } else {
            value >= self.lower
        };
        above && value <= self.upper
    }
}

impl MaterialState {
    /// The state variables with a valid range beyond finiteness (the relative volume's
    /// `V/V0 > 0` is checked with finiteness, [`crate::UpdateError::NonFiniteState`]).
    pub const CHECKED_VARIABLES: [StateVariable; 4] = [
        StateVariable {
            name: "plastic_strain",
            unit: "-",
            lower: 0.0,
            lower_excluded: false,
            upper: f64::INFINITY,
        },
        StateVariable {
            name: "plastic_strain_rate",
            unit: "1/s",
            lower: 0.0,
            lower_excluded: false,
            upper: f64::INFINITY,
        },
        StateVariable {
            name: "temperature",
            unit: "K",
            lower: 0.0,
            lower_excluded: true,
            upper: f64::INFINITY,
        },
        StateVariable {
            name: "damage",
            unit: "-",
            lower: 0.0,
            lower_excluded: false,
            upper: 1.0,
        },
    ];

    /// The first variable of [`Self::CHECKED_VARIABLES`] outside its valid range, with its
    /// value (for a finite state).
    #[inline]
    pub fn inadmissible(&self) -> Option<(&'static StateVariable, f64)> {
        let values = [
            self.plastic_strain,
            self.plastic_strain_rate,
            self.temperature,
            self.damage,
        ];
        Self::CHECKED_VARIABLES
            .iter()
            .zip(values)
            .find(|(variable, value)| !variable.admits(*value))
    }

    /// Undeformed, stress-free state at temperature `temperature` (K).
    pub const fn initial(temperature: f64) -> Self {
        Self {
            stress: tensor::ZERO,
            plastic_strain: 0.0,
            plastic_strain_rate: 0.0,
            temperature,
            damage: 0.0,
            relative_volume: 1.0,
            internal_energy: 0.0,
            eos_history: 0.0,
            flags: StateFlags(0),
            yield_check: YieldCheck::NONE,
        }
    }

    /// Pressure `p = -tr(sigma)/3`.
    #[inline]
    pub fn pressure(&self) -> f64 {
        tensor::pressure(&self.stress)
    }

    /// von Mises equivalent stress.
    #[inline]
    pub fn equivalent_stress(&self) -> f64 {
        tensor::von_mises(&tensor::deviator(&self.stress))
    }

    /// The thirteen stored values (stress, then the scalars in declaration order).
    #[inline(always)]
    pub fn values(&self) -> [f64; 13] {
        let s = &self.stress;
        [
            s[0],
            s[1],
            s[2],
            s[3],
            s[4],
            s[5],
            self.plastic_strain,
            self.plastic_strain_rate,
            self.temperature,
            self.damage,
            self.relative_volume,
            self.internal_energy,
            self.eos_history,
        ]
    }

    /// `true` if every stored value is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        crate::math::all_finite(&self.values())
    }
}
