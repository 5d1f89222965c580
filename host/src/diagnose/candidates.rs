//! The library of candidate physics terms. Each is a nested extension of the calibrated model:
//! one new constant `gamma` with a null value at which the extended model is the current model
//! exactly (bit for bit; checked by a test for every term), so the score test can ask whether
//! moving `gamma` away from its null would explain the misfit.
//!
//! | term | extension | gamma (null) |
//! |---|---|---|
//! | `adiabatic-heating` | isothermal -> `dT = chi sigma deps_p / (rho c_p)` | `chi` (0) |
//! | `heating-transition-a-b` | isothermal -> isothermal below `a`, adiabatic above `b = 100 a` (`a` = 1e-3 ... 10 /s: one term over a grid of windows) | `chi` (0) |
//! | `high-rate-upturn` | JC rate `1 + C ln e*` -> `(1 + C ln e*)(1 + deps_p/1000)^beta` | `beta` (0) |
//! | `voce-saturation` | `A + B eps^n` -> `+ Q1 (1 - exp(-20 eps))` | `Q1` (0) |
//! | `thermal-softening` | JC `1 - T*^m` with `m` fixed -> `m` fitted | `m` (its value) |
//! | `thermal-drop-<Td>` | `1 - T*^m` -> `(1 - T*^m)(1 - d S(T))`, `S` a smooth step over `Td +- wd/2`: a second softening stage (`Td` over a grid inside the temperatures the experiments reach: one term) | `d` (0) |
//! | `rate-temperature-coupling` | `C` -> `C (1 + kappa T*)` (ZA-like) | `kappa` (0) |
//! | `anvil-friction` | Taylor anvil friction `mu` fitted | `mu` (its value, 0) |
//! | `erosion` | elements erode at `eps_f = 1/gamma` | `gamma` (0) |
//! | `eos-nonlinearity` | linear `K mu` -> `K mu + A2 mu^2` (Grüneisen-like stiffening) | `A2` (0) |
//! | `lagged-rate` | predictions `(1 - lambda) P + lambda P(lagged rate, seed 001 eq. 3.7)` | `lambda` (0) |
//!
//! Fixed shape constants (the upturn rate 1000 /s, the Voce rate 20) are the nuisance
//! constants that a score test must fix (they are not identified at the null); the values are
//! typical of armour steels and are named in the report. The heating transition's window is
//! not fixed: its variants over a grid are tested as one term (see [`Candidate::group`]); so is
//! the thermal drop's centre, over [`DROP_CENTRES`] points spread inside the temperatures the
//! experiments reach, each drop [`DROP_WIDTH_SPACINGS`] grid spacings wide.

use crate::experiment::Setup;
use crate::fit::campaign::RecordingSource;
use crate::fit::hypothesis::{
    other_rate_treatment, Hypothesis, Parameter, ANVIL_FRICTION, EROSION_INTENSITY, LAGGED_MIXTURE,
};
use crate::fit::Campaign;
use crate::input::material::StrengthSpec;
use serde::{Deserialize, Serialize};
use stoss_kernel::eos::{Eos, Polynomial};
use stoss_kernel::strength::{ComposedStrength, Hardening, RateTerm, ThermalTerm};
use stoss_kernel::{Heating, RateTreatment};

/// Upturn rate of the high-rate term (1/s).
pub const UPTURN_RATE: f64 = 1.0e3;
/// Saturation rate of the Voce term (-).
pub const VOCE_RATE: f64 = 20.0;
/// Isothermal ends of the heating-transition windows tried (1/s); each window is adiabatic
/// above [`TRANSITION_WIDTH`] times its isothermal end. Where a material turns adiabatic is a
/// nuisance constant of the term that the recordings, not the library, should choose: the
/// windows are one term over a grid (the best counts, its p-value multiplied by the grid's
/// size).
pub const TRANSITION_STARTS: [f64; 5] = [1.0e-3, 1.0e-2, 1.0e-1, 1.0, 1.0e1];
/// Ratio of the adiabatic to the isothermal end of a heating-transition window (two decades).
pub const TRANSITION_WIDTH: f64 = 100.0;

/// The name of the heating-transition window starting at `isothermal_rate`, e.g.
/// `heating-transition-0.01-1`.
pub fn transition_name(isothermal_rate: f64) -> String {
    let rate = |r: f64| {
        let text = format!("{r}");
        text.trim_end_matches(".0").to_string()
    };
    format!(
        "heating-transition-{}-{}",
        rate(isothermal_rate),
        rate(isothermal_rate * TRANSITION_WIDTH)
    )
}

/// Centres of the thermal-drop variants: evenly inside the temperature range the experiments
/// reach (at their plastic samples), `(k + 1/2) / DROP_CENTRES` of the way across.
pub const DROP_CENTRES: usize = 5;
/// Width of a thermal drop in grid spacings (adjacent variants overlap, so a drop between two
/// centres is seen by both).
pub const DROP_WIDTH_SPACINGS: f64 = 2.0;
/// Smallest temperature range (K) over which a thermal drop is tried: below it the
/// experiments cannot tell a drop from the softening exponent.
pub const DROP_MINIMUM_RANGE: f64 = 100.0;

/// What the current model's simulations reach, which places some terms' steps and grids.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Visited {
    /// Largest plastic strain reached.
    pub max_plastic_strain: f64,
    /// Lowest and highest temperature at a plastically flowing sample (K), if any flowed.
    pub temperatures: Option<(f64, f64)>,
}

impl Visited {
    /// From the tracked states of the current model's outcomes.
    pub fn from_outcomes(outcomes: &[Option<crate::experiment::Outcome>]) -> Self {
        let samples = outcomes
            .iter()
            .flatten()
            .flat_map(|o| o.states.iter())
            .flat_map(|h| h.samples.iter());
        let mut visited = Visited::default();
        for sample in samples {
            visited.max_plastic_strain = visited.max_plastic_strain.max(sample.plastic_strain);
            if sample.plastic_strain > 0.0 && sample.temperature.is_finite() {
                let t = sample.temperature;
                visited.temperatures = Some(match visited.temperatures {
                    None => (t, t),
                    Some((low, high)) => (low.min(t), high.max(t)),
                });
            }
        }
        visited
    }
}

/// The name of the thermal-drop variant centred at `temperature` (K), e.g. `thermal-drop-950K`.
pub fn drop_name(temperature: f64) -> String {
    format!("thermal-drop-{temperature:.0}K")
}

/// A candidate term, ready to test.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Candidate {
    /// Short name.
    pub name: String,
    /// What physics it adds, in words.
    pub physics: String,
    /// Its constant and the bounds of the refit.
    pub parameter: Parameter,
    /// The null value (gives back the current model).
    pub null: f64,
    /// Finite-difference step from the null for the score (SI).
    pub step: f64,
    /// Only values on the step's side of the null are physical (one-sided test).
    pub one_sided: bool,
    /// The current model extended by the term, at its null (the term's constant last).
    pub extended: Hypothesis,
    /// The refit switches the rate treatment instead of fitting the term's constant (the
    /// lagged-rate term: its mixture weight exists only for the score test).
    pub switches_rate_treatment: bool,
    /// What the term adds when the recordings ask for its constant below the null, if that
    /// reads differently from [`Self::physics`] (a two-sided term: the coupling of rate and
    /// temperature with a negative constant is a rate sensitivity *falling* with temperature).
    #[serde(default)]
    pub physics_below: Option<String>,
    /// The term this candidate is one variant of, over a grid of a fixed shape constant
    /// (`heating-transition` for its windows); its own name otherwise. The score tests keep
    /// the best variant of a group and multiply its p-value by the group's size.
    #[serde(default)]
    pub group: String,
}

/// A term of the library that does not apply to this model, and why.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct NotApplicable {
    /// Short name.
    pub name: String,
    /// Why not.
    pub reason: String,
}

fn extend(
    current: &Hypothesis,
    name: &str,
    physics: &str,
    parameter: Parameter,
    null: f64,
    step: f64,
    change: impl FnOnce(&mut Hypothesis),
) -> Candidate {
    let mut extended = current.clone();
    extended.label = name.into();
    change(&mut extended);
    extended.parameters.push(parameter.clone());
    Candidate {
        name: name.into(),
        physics: physics.into(),
        one_sided: null <= parameter.lower,
        parameter,
        null,
        step,
        extended,
        switches_rate_treatment: false,
        physics_below: None,
        group: name.into(),
    }
}

/// The library for `current` (the calibrated model with its fitted values written in).
/// `visited` is what the current model reaches in the experiments (the largest plastic strain
/// places the erosion term's finite-difference step, the temperature range the thermal drop's
/// grid).
pub fn library(
    current: &Hypothesis,
    campaign: &Campaign,
    visited: &Visited,
) -> (Vec<Candidate>, Vec<NotApplicable>) {
    let mut library = Library {
        current,
        candidates: Vec::new(),
        skipped: Vec::new(),
    };
    library.heating();
    match current.material.strength {
        StrengthSpec::Composed(strength) => {
            library.rate_terms(&strength);
            library.voce_saturation(&strength);
            library.thermal_softening(&strength);
            library.thermal_drop(&strength, visited);
        }
        _ => {
            for name in [
                "high-rate-upturn",
                "voce-saturation",
                "thermal-softening",
                "thermal-drop",
                "rate-temperature-coupling",
            ] {
                library.skip(
                    name,
                    "the strength family is not written in composable terms (use johnson-cook or composed)".into(),
                );
            }
        }
    }
    library.anvil_friction(campaign);
    library.erosion(visited.max_plastic_strain);
    library.eos_nonlinearity();
    if campaign.file.recordings == RecordingSource::Simulation {
        library.lagged_rate();
    } else {
        library.skip(
            "lagged-rate",
            "a rate update of an FE code, not a property of a material: offered only for \
             recordings that are simulations (the campaign's `recordings = \"simulation\"`)"
                .into(),
        );
    }
    (library.candidates, library.skipped)
}

/// The library being built: the terms that apply to `current`, and those that do not.
struct Library<'a> {
    current: &'a Hypothesis,
    candidates: Vec<Candidate>,
    skipped: Vec<NotApplicable>,
}

impl Library<'_> {
    fn skip(&mut self, name: &str, reason: String) {
        self.skipped.push(NotApplicable {
            name: name.into(),
            reason,
        });
    }

    /// Whether the current model fits the constant at `path`.
    fn fitted(&self, path: &str) -> bool {
        self.current.parameters.iter().any(|p| p.name == path)
    }

    /// Adiabatic heating, and the heating transitions over their grid of windows (an
    /// isothermal model only).
    fn heating(&mut self) {
        let current = self.current;
        if current.material.heating != Heating::Isothermal {
            let reason = "the model already converts plastic work into heat".to_string();
            self.skip("adiabatic-heating", reason.clone());
            self.skip("heating-transition", reason);
            return;
        }
        let chi = Parameter {
            name: "heating.taylor_quinney".into(),
            lower: 0.0,
            upper: 1.0,
        };
        self.candidates.push(extend(
            current,
            "adiabatic-heating",
            "adiabatic heating (plastic work raises the temperature and softens the material)",
            chi.clone(),
            0.0,
            0.3,
            |h| {
                h.material.heating = Heating::Adiabatic {
                    taylor_quinney: 0.0,
                }
            },
        ));
        for isothermal_rate in TRANSITION_STARTS {
            let adiabatic_rate = isothermal_rate * TRANSITION_WIDTH;
            let mut candidate = extend(
                current,
                &transition_name(isothermal_rate),
                &format!(
                    "a rate-dependent isothermal-to-adiabatic transition (isothermal below {isothermal_rate} /s, adiabatic above {adiabatic_rate} /s)"
                ),
                chi.clone(),
                0.0,
                0.3,
                |h| {
                    h.material.heating = Heating::Transition {
                        taylor_quinney: 0.0,
                        isothermal_rate,
                        adiabatic_rate,
                    }
                },
            );
            candidate.group = "heating-transition".into();
            self.candidates.push(candidate);
        }
    }

    /// The high-rate upturn and the rate-temperature coupling (a Johnson-Cook log rate term
    /// only).
    fn rate_terms(&mut self, strength: &ComposedStrength) {
        let current = self.current;
        let RateTerm::JohnsonCookLog {
            rate_sensitivity,
            reference_rate,
        } = strength.rate
        else {
            let reason = "the rate term is not Johnson-Cook's logarithm".to_string();
            self.skip("high-rate-upturn", reason.clone());
            self.skip("rate-temperature-coupling", reason);
            return;
        };
        self.candidates.push(extend(
            current,
            "high-rate-upturn",
            "a high-rate upturn of the flow stress (power-law rate term above ~1000 /s)",
            Parameter {
                name: "strength.rate.upturn_exponent".into(),
                lower: 0.0,
                upper: 0.5,
            },
            0.0,
            0.05,
            |h| {
                if let StrengthSpec::Composed(c) = &mut h.material.strength {
                    c.rate = RateTerm::LogUpturn {
                        rate_sensitivity,
                        reference_rate,
                        upturn_exponent: 0.0,
                        upturn_rate: UPTURN_RATE,
                    };
                }
            },
        ));
        let (reference_temperature, melting_temperature) = strength
            .thermal
            .temperature_limits()
            .unwrap_or((298.0, 1793.0));
        let mut coupling = extend(
            current,
            "rate-temperature-coupling",
            "rate-temperature coupling (rate sensitivity growing with temperature, as in Zerilli-Armstrong)",
            Parameter {
                name: "strength.rate.coupling".into(),
                lower: -1.0,
                upper: 10.0,
            },
            0.0,
            1.0,
            |h| {
                if let StrengthSpec::Composed(c) = &mut h.material.strength {
                    c.rate = RateTerm::LogThermal {
                        rate_sensitivity,
                        reference_rate,
                        coupling: 0.0,
                        reference_temperature,
                        melting_temperature,
                    };
                }
            },
        );
        coupling.physics_below =
            Some("rate-temperature coupling (rate sensitivity falling with temperature)".into());
        self.candidates.push(coupling);
    }

    /// Voce saturation added to power-law hardening.
    fn voce_saturation(&mut self, strength: &ComposedStrength) {
        let Hardening::Power {
            yield_stress,
            hardening_modulus,
            exponent,
        } = strength.hardening
        else {
            self.skip(
                "voce-saturation",
                "the hardening term already saturates (Voce)".into(),
            );
            return;
        };
        self.candidates.push(extend(
            self.current,
            "voce-saturation",
            "saturating (Voce) strain hardening",
            Parameter {
                name: "strength.hardening.saturation_stress_1".into(),
                lower: 0.0,
                upper: 1.0e9,
            },
            0.0,
            0.1e9,
            |h| {
                if let StrengthSpec::Composed(c) = &mut h.material.strength {
                    c.hardening = Hardening::PowerVoce2 {
                        yield_stress,
                        hardening_modulus,
                        exponent,
                        saturation_stress_1: 0.0,
                        saturation_rate_1: VOCE_RATE,
                        saturation_stress_2: 0.0,
                        saturation_rate_2: VOCE_RATE,
                    };
                }
            },
        ));
    }

    /// The thermal-softening exponent, fitted (a `1 - T*^m` term whose `m` is fixed).
    fn thermal_softening(&mut self, strength: &ComposedStrength) {
        match strength.thermal {
            ThermalTerm::HomologousPower { exponent, .. }
                if !self.fitted("strength.thermal.exponent") =>
            {
                let mut softening = extend(
                    self.current,
                    "thermal-softening",
                    "a different thermal-softening shape (a larger exponent m of 1 - T*^m: softening delayed to higher temperatures)",
                    Parameter {
                        name: "strength.thermal.exponent".into(),
                        lower: 0.5,
                        upper: 1.5,
                    },
                    exponent,
                    if exponent + 0.1 <= 1.5 { 0.1 } else { -0.1 },
                    |_| {},
                );
                softening.physics_below = Some(
                    "a different thermal-softening shape (a smaller exponent m of 1 - T*^m: softening from lower temperatures on)"
                        .into(),
                );
                self.candidates.push(softening);
            }
            ThermalTerm::HomologousPower { .. } => self.skip(
                "thermal-softening",
                "the thermal exponent is already fitted".into(),
            ),
            _ => self.skip(
                "thermal-softening",
                "the thermal term is not 1 - T*^m".into(),
            ),
        }
    }

    /// A second thermal-softening stage over its grid of centres inside the temperatures the
    /// experiments reach (a `1 - T*^m` term, a wide enough range).
    fn thermal_drop(&mut self, strength: &ComposedStrength, visited: &Visited) {
        match (strength.thermal, visited.temperatures) {
            (
                ThermalTerm::HomologousPower {
                    exponent,
                    reference_temperature,
                    melting_temperature,
                },
                Some((low, high)),
            ) if high - low >= DROP_MINIMUM_RANGE => {
                let spacing = (high - low) / DROP_CENTRES as f64;
                for k in 0..DROP_CENTRES {
                    let drop_temperature = low + (k as f64 + 0.5) * spacing;
                    let drop_width = DROP_WIDTH_SPACINGS * spacing;
                    let mut candidate = extend(
                        self.current,
                        &drop_name(drop_temperature),
                        &format!(
                            "a second thermal-softening stage (a strength drop around {drop_temperature:.0} K, over {:.0}-{:.0} K)",
                            drop_temperature - 0.5 * drop_width,
                            drop_temperature + 0.5 * drop_width
                        ),
                        Parameter {
                            name: "strength.thermal.drop".into(),
                            lower: 0.0,
                            upper: 0.9,
                        },
                        0.0,
                        0.1,
                        |h| {
                            if let StrengthSpec::Composed(c) = &mut h.material.strength {
                                c.thermal = ThermalTerm::HomologousPowerDrop {
                                    exponent,
                                    reference_temperature,
                                    melting_temperature,
                                    drop: 0.0,
                                    drop_start_temperature: drop_temperature - 0.5 * drop_width,
                                    drop_end_temperature: drop_temperature + 0.5 * drop_width,
                                };
                            }
                        },
                    );
                    candidate.group = "thermal-drop".into();
                    self.candidates.push(candidate);
                }
            }
            (ThermalTerm::HomologousPower { .. }, _) => self.skip(
                "thermal-drop",
                format!("the experiments' plastic flow spans less than {DROP_MINIMUM_RANGE} K"),
            ),
            _ => self.skip("thermal-drop", "the thermal term is not 1 - T*^m".into()),
        }
    }

    /// Coulomb friction at the anvil (Taylor tests sharing one unfitted friction).
    fn anvil_friction(&mut self, campaign: &Campaign) {
        let frictions: Vec<f64> = campaign
            .experiments
            .iter()
            .filter_map(|e| match &e.file.setup {
                Setup::Taylor(spec) => Some(spec.anvil_friction),
                _ => None,
            })
            .collect();
        let shared = frictions.first().copied();
        match shared {
            Some(mu) if frictions.iter().all(|f| *f == mu) && !self.fitted(ANVIL_FRICTION) => {
                self.candidates.push(extend(
                    self.current,
                    "anvil-friction",
                    "friction between the rod and the anvil (Coulomb)",
                    Parameter {
                        name: ANVIL_FRICTION.into(),
                        lower: 0.0,
                        upper: 0.5,
                    },
                    mu,
                    0.1,
                    |h| h.anvil_friction = Some(mu),
                ));
            }
            Some(_) => self.skip(
                "anvil-friction",
                "the Taylor tests differ in their anvil friction or it is fitted".into(),
            ),
            None => self.skip("anvil-friction", "no Taylor test in the campaign".into()),
        }
    }

    /// Erosion at a critical plastic strain (a material without failure that flows).
    fn erosion(&mut self, max_plastic_strain: f64) {
        if !(self.current.material.failure.is_none() && max_plastic_strain > 0.0) {
            self.skip(
                "erosion",
                "the material already has a failure model, or no plastic strain is reached".into(),
            );
            return;
        }
        // Step: failure at 90 % of the largest plastic strain reached, so the term acts.
        let step = 1.0 / (0.9 * max_plastic_strain);
        self.candidates.push(extend(
            self.current,
            "erosion",
            "damage and failure (elements erode at a critical plastic strain)",
            Parameter {
                name: EROSION_INTENSITY.into(),
                lower: 0.0,
                upper: 4.0 * step,
            },
            0.0,
            step,
            |_| {},
        ));
    }

    /// A quadratic term added to a linear equation of state.
    fn eos_nonlinearity(&mut self) {
        let Eos::Linear(linear) = self.current.material.eos else {
            self.skip(
                "eos-nonlinearity",
                "the equation of state is already nonlinear".into(),
            );
            return;
        };
        let k = linear.bulk_modulus;
        self.candidates.push(extend(
            self.current,
            "eos-nonlinearity",
            "a nonlinear (Grüneisen-like, stiffening) equation of state",
            Parameter {
                name: "eos.a2".into(),
                lower: 0.0,
                upper: 5.0 * k,
            },
            0.0,
            k,
            |h| h.material.eos = Eos::Polynomial(Polynomial::linear(k)),
        ));
    }

    /// The seed 001 rate-treatment defect: the recordings behave as the other rate update.
    fn lagged_rate(&mut self) {
        let other = match self.current.material.rate_treatment {
            RateTreatment::Implicit => "lagged (seed 001 eq. 3.7)",
            RateTreatment::Lagged => "implicit (seed 001 eq. 3.8)",
        };
        let mut lagged = extend(
            self.current,
            "lagged-rate",
            &format!(
                "the rate-treatment defect of seed 001: the recordings behave as a {other} rate update"
            ),
            Parameter {
                name: LAGGED_MIXTURE.into(),
                lower: 0.0,
                upper: 1.0,
            },
            0.0,
            1.0,
            |_| {},
        );
        lagged.switches_rate_treatment = true;
        self.candidates.push(lagged);
    }
}

impl Candidate {
    /// The hypothesis the refit fits and its starting values (`current_values`: the current
    /// model's fitted constants).
    pub fn refit(&self, current_values: &[f64]) -> (Hypothesis, Vec<f64>) {
        if self.switches_rate_treatment {
            let mut hypothesis = self.extended.clone();
            hypothesis.parameters.pop();
            hypothesis.material.rate_treatment =
                other_rate_treatment(hypothesis.material.rate_treatment);
            return (hypothesis, current_values.to_vec());
        }
        let mut start = current_values.to_vec();
        start.push(self.null);
        (self.extended.clone(), start)
    }
}
