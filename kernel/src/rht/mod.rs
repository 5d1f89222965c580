//! The RHT concrete model (Riedel, Hiermaier, Thoma; Riedel 2000, as implemented in Autodyn
//! 4.2 and used by seed 001, FOI-R--0281--SE (2001), chapter 4): pressure-dependent failure,
//! elastic-limit (with cap) and residual surfaces, Lode-angle dependence, strain-rate
//! enhancement, linear hardening, damage softening, tensile failure, over the crate's EoS
//! (normally [`crate::eos::Eos::PAlpha`]).
//!
//! # Equations (seed 001 eqs. 4.1-4.9, `p* = p/fc`, strengths are `sigma_eq = sqrt(3 J2)`)
//!
//! ```text
//! failure      Y_fail  = fc F^(1+k) R3(theta, Q2(p*)) g(p*/F)                 (4.1, 4.5)
//!              g(p*)   = A (p* - p*_0)^N              for p* >= 1/3, p*_0 = 1/3 - A^(-1/N)
//!                        (below 1/3: the power law, or the characteristic-point lines)
//! Lode         R3      = [2(1-Q2^2)cos t + (2Q2-1) sqrt(4(1-Q2^2)cos^2 t + 5Q2^2 - 4Q2)]
//!                        / [4(1-Q2^2)cos^2 t + (1-2Q2)^2]                        (4.2)
//!              Q2      = Q2,0 + BQ p*, 0.5 <= Q2 <= 1                            (4.3)
//! rate         F       = (rate/30e-6)^alpha  (p >= fc/3),  (rate/3e-6)^delta (p <= -ft/3),
//!                        linear in p between, >= 1                               (4.4)
//! elastic      Y_el    = F_e Y_fail(p/F_e) F_cap(p) <= Y_fail
//! hardening    Y       = Y_el + min(eps_p/eps_pre, 1) (Y_fail - Y_el),
//!              eps_pre = (Y_fail - Y_el)(PREFACT - 1)/(3G)
//! damage       D       = sum(d eps_p / eps_f), eps_f = max(D1 (p* - p*_spall)^D2, EFMIN)  (4.6, 4.7)
//! residual     Y_resid = fc B p*^M (p* > 0), 0 otherwise, capped at Y_fail       (4.8)
//! damaged      Y       = (1 - D) Y_fail + D Y_resid                              (4.9)
//! ```
//!
//! # What was restored, and from what
//!
//! The seed's extraction kept the bodies of eqs. 4.1-4.9 but not the definitions they rely
//! on, and only names the elastic surface, cap and hardening. The gaps are filled from the
//! model's public descriptions (the Ansys Autodyn / Explicit Dynamics manual section on RHT
//! concrete, LS-DYNA `*MAT_RHT` and Grunwald et al. 2017, which reproduce Riedel 2000);
//! Riedel's thesis itself was not available, so each choice below says what it rests on.
//! - **`p*_spall` in eq. 4.1.** Not defined in the seed. The power law is anchored at the
//!   uniaxial compression point, `g(1/3) = 1`, which gives its pressure-axis intercept
//!   `p*_0 = 1/3 - A^(-1/N)` (-0.0098 for table 4.4). This is what makes `fc` the uniaxial
//!   compressive strength (Riedel 2000; LS-DYNA `*MAT_RHT` writes the same anchor as
//!   `A (p* - F/3 + (A/F)^(-1/N))^N`). With the truncated meridian below, `p*_spall` (the
//!   Ansys documentation's "normalised hydrodynamic tensile limit") is where the whole
//!   meridian meets the pressure axis, and is also the `p*_spall` of eq. 4.7 and the hydro
//!   tensile limit.
//! - **Low-pressure meridian.** The seed's table gives `ft/fc` and `fs/fc`, which eq. 4.1
//!   alone does not use; Autodyn's option "truncate the failure surface to fit through the
//!   characteristic points observed at low pressures" (Ansys Explicit Dynamics manual, RHT
//!   concrete) does: uniaxial tension `(-FT*/3, FT*/Q2)`, pure shear `(0, FS*/R3(pi/6))`,
//!   uniaxial compression `(1/3, 1)`, straight lines between (the tension-shear line extended
//!   to zero strength at `p*_spall`), eq. 4.1 above. This is
//!   [`FailureMeridian::CharacteristicPoints`] (the table 4.4 constant);
//!   [`FailureMeridian::PowerLaw`] keeps eq. 4.1 everywhere. `FS*` is read as the equivalent-stress ratio at pure shear (as in
//!   LS-DYNA's `F_s/Q1` term): with it, the table 4.4 meridian is convex (slopes 16.3,
//!   1.82, 1.75 per unit `p*`), with `FS*` as a shear-stress ratio it would not be.
//! - **Rate factor eq. 4.4.** The second branch reads "for P < fc/3" in the extraction,
//!   which leaves no transition; restored as `p <= -ft/3` (tension, `delta`, 3e-6 /s), with
//!   Autodyn's linear interpolation in pressure between `-ft/3` and `fc/3`. `F >= 1`: rates
//!   below the references do not weaken the material. The rate is the total (not plastic) strain rate of the step, as
//!   for concrete DIF data, measured as the largest absolute principal strain rate
//!   ([`strain_rate`]): the axial rate of a uniaxial stress or strain test whatever the
//!   lateral strains do. (An effective deviatoric rate `sqrt(2/3 de:de)` would vary
//!   between 0.79 and 1 times the axial rate through a uniaxial test as the lateral
//!   strain ratio changes, moving the rate factor in the middle of a test.)
//! - **Where `F_rate` enters.** Eq. 4.5 multiplies the surface by `F_rate` and eq. 4.1 also
//!   shifts the intercept by it. [`RateScaling::SeedEquation`] keeps both: on the power-law
//!   branch `Y_fail = fc F A (p* - p*_0 F)^N R3`, exactly the printed equations, and the
//!   whole meridian (truncated part included) is written `F^(1+N) g(p*/F)`, continuous and
//!   equal to it there. The uniaxial DIF is then about `F^(1/(1-N))`, larger than `F`,
//!   which is the "pressure effects included" of seed fig. 4.12.
//!   [`RateScaling::Homothetic`] (`F g(p*/F)`) gives a uniaxial DIF equal to `F`.
//! - **Elastic surface, cap.** Only named in the seed (PREFACT, COMPRAT, TENSRAT, "cap").
//!   Restored from Riedel 2000 / the Autodyn manual: the failure surface scaled about the
//!   origin by `F_e` (`COMPRAT` in compression above `p* = COMPRAT F/3`, `TENSRAT` in tension
//!   below `p* = -TENSRAT FT* F/3`, linear between), so the elastic limits on the uniaxial
//!   paths are `COMPRAT fc` and `TENSRAT ft`; the cap is the quarter ellipse
//!   `sqrt(1 - ((p - p_u)/(p_0 - p_u))^2)` from `p_u = COMPRAT fc/3` to the pore-crush
//!   pressure `p_0` of the P-alpha EoS (no elastic deviatoric range beyond it).
//! - **Hardening.** Linear between elastic and failure surface in `eps_p`, normalised by
//!   the pre-softening strain; `PREFACT = G/G_ep` read as the ratio of the elastic slope to
//!   the elastic-plastic slope of `sigma_eq` against total strain, giving `H = 3G/(PREFACT-1)`.
//!   Damage accumulates only for plastic strain beyond the failure surface (seed: "the
//!   damage grows after the stress point passes the failure surface"); once `D > 0` the
//!   hardening is complete.
//! - **Residual surface** (eq. 4.8) is used as printed: no Lode or rate factor, zero in
//!   tension, never above the failure surface.
//! - **Shear modulus with damage** `G (1 - D + D SHRATD)` (Autodyn's SHRATD).
//!
//! # Numerics
//! The return is radial in the deviatoric plane at fixed pressure and Lode angle and is
//! solved in closed form (the current strength is piecewise linear in the plastic
//! multiplier), so [`StepOutput::iterations`] is 0. The tangent of [`update_with_tangent`]
//! is a central-difference one. See [`update()`] for the order of operations.
//!
//! # Flags
//! [`crate::StateFlags::FAILED`] is set when `D` reaches 1: for RHT that means *residual
//! strength only* (strength `min(Y_resid, Y_fail)`, no tension), not deletion.
//! [`crate::StateFlags::ERODE`] is set by [`RhtMaterial::erosion_plastic_strain`] in the
//! update, and by the host from [`RhtMaterial::erosion_geometric_strain`] (Autodyn's
//! instantaneous geometric strain, which needs the element's deformation).
//! [`crate::StateFlags::PRESSURE_CUTOFF`] marks a step whose pressure was held at the
//! hydro tensile limit (or at 0 after failure).
//!
//! # Tension: three options
//! [`TensileFailure::HydroTensileLimit`] (Autodyn's, the seed's table 4.4) fails the point
//! outright when its pressure would fall below `p_min`; [`TensileFailure::PrincipalStress`]
//! when the largest principal stress reaches `ft`; [`TensileFailure::PressureCutoff`]
//! (LS-DYNA `*MAT_RHT`, Borrvall & Riedel 2011) only holds the pressure at `p_min`, and
//! tensile damage then grows from plastic strain like any other. In a structure the first
//! two fail concrete wherever a diverging stress wave leaves a few MPa of mean tension behind
//! it (far from the loaded zone); the third confines damage to where the material flows.

mod parameters;
mod surfaces;
pub(crate) mod update;

pub use parameters::{FailureMeridian, RateScaling, RhtParameters, TensileFailure};
pub use surfaces::{lode_factor_from_cos, Lode, Surfaces, COS_SHEAR_MERIDIAN};
pub use update::{strain_rate, update, update_with_tangent};

use crate::damage::Failure;
use crate::eos::{Eos, PAlpha, Polynomial};
use crate::error::{check, ParameterError, UpdateError};
use crate::point_model::PointModel;
use crate::point_model::{StepInput, StepOutput};
use crate::state::{MaterialState, StateFlags};
use crate::tensor::Matrix6;

/// A complete RHT material: density, RHT constants, EoS, erosion.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct RhtMaterial {
    /// Reference (porous) density `rho0` (kg/m^3).
    pub density: f64,
    /// Strength, damage and rate constants.
    pub parameters: RhtParameters,
    /// Equation of state; the elastic cap needs [`Eos::PAlpha`] (its crush pressure closes
    /// the cap).
    pub eos: Eos,
    /// Equivalent plastic strain at which the host should erode the element (seed 001 table
    /// 4.5 uses 1.5 for its Lagrange targets). `None`: never.
    pub erosion_plastic_strain: Option<f64>,
    /// Autodyn-style *instantaneous geometric strain* at which the host erodes the element
    /// (seed 001 table 4.5: 1.5 for the concrete targets), evaluated by the host FE code from
    /// the element's deformation, as for the metals ([`crate::damage::Failure::geometric_strain`]).
    /// `None`: never.
    #[cfg_attr(feature = "serde", serde(default))]
    pub erosion_geometric_strain: Option<f64>,
}

impl RhtMaterial {
    /// Seed 001 table 4.4 HPC ([`RhtParameters::HPC_92MPA`]) with density 2420 kg/m^3
    /// (seed table 5.1, the same concrete) over an **illustrative** P-alpha EoS: the seed
    /// gives no P-alpha constants (its EoS is fitted to a figure). Chosen: matrix density
    /// 2750 kg/m^3 (Autodyn's concrete matrix), so `alpha0 = 2750/2420`; `A1 = T1 = 24.4 GPa`
    /// so that the elastic porous bulk modulus `A1/alpha0` is the seed's 21.5 GPa (section
    /// 4.3.1); `A2 = 39.58 GPa`, `A3 = 9.04 GPa`, `B0 = B1 = 1.22` (Riedel's matrix); crush
    /// pressure `2/3 fc = 61.3 MPa` (the ratio of Riedel's 35 MPa concrete, 23.3 MPa; it
    /// must exceed `COMPRAT fc/3 = 23 MPa` and, for unconfined compression not to compact,
    /// the dynamic `DIF fc/3`, 47 MPa at 1000 /s); lock pressure 6 GPa, exponent 3 (Autodyn defaults). No
    /// erosion.
    pub const HPC_92MPA: RhtMaterial = RhtMaterial {
        density: 2420.0,
        parameters: RhtParameters::HPC_92MPA,
        eos: Eos::PAlpha(PAlpha {
            solid: Polynomial {
                a1: 24.4e9,
                a2: 39.58e9,
                a3: 9.04e9,
                b0: 1.22,
                b1: 1.22,
                t1: 24.4e9,
                t2: 0.0,
            },
            initial_distension: 2750.0 / 2420.0,
            crush_pressure: 2.0 / 3.0 * 92.0e6,
            lock_pressure: 6.0e9,
            exponent: 3.0,
        }),
        erosion_plastic_strain: None,
        erosion_geometric_strain: None,
    };

    /// Pore-crush pressure closing the elastic cap, when the cap is on and the EoS has one.
    pub fn cap_pressure(&self) -> Option<f64> {
        match (&self.eos, self.parameters.elastic_cap) {
            (Eos::PAlpha(eos), true) => Some(eos.crush_pressure),
            _ => None,
        }
    }

    /// A fresh state at temperature `temperature` (K), with the EoS history seeded
    /// (`alpha0` for P-alpha).
    pub fn initial_state(&self, temperature: f64) -> MaterialState {
        let mut state = MaterialState::initial(temperature);
        state.eos_history = self.eos.initial_history();
        state
    }

    /// Validate every part; the first offending field is reported. The cap needs a P-alpha
    /// EoS whose crush pressure exceeds `COMPRAT fc/3`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::positive("density", self.density)?;
        self.parameters.validate()?;
        self.eos.validate()?;
        if self.parameters.elastic_cap {
            let Eos::PAlpha(eos) = &self.eos else {
                return Err(ParameterError::Inconsistent {
                    field: "elastic_cap",
                    other: "eos",
                });
            };
            let pu = self.parameters.compressive_elastic_ratio
                * self.parameters.compressive_strength
                / 3.0;
            if eos.crush_pressure <= pu {
                return Err(ParameterError::Inconsistent {
                    field: "crush_pressure",
                    other: "compressive_elastic_ratio",
                });
            }
        }
        if let Some(strain) = self.erosion_plastic_strain {
            check::positive("erosion_plastic_strain", strain)?;
        }
        if let Some(strain) = self.erosion_geometric_strain {
            check::positive("erosion_geometric_strain", strain)?;
        }
        Ok(())
    }
}

impl RhtMaterial {
    /// RHT's only kinematic criterion, the geometric erosion strain, as the metals' failure
    /// settings evaluate it.
    fn kinematic_failure(&self) -> Failure {
        Failure {
            erosion_geometric_strain: self.erosion_geometric_strain,
            ..Failure::NONE
        }
    }
}

impl PointModel for RhtMaterial {
    fn validate(&self) -> Result<(), ParameterError> {
        RhtMaterial::validate(self)
    }

    fn shear_modulus(&self) -> f64 {
        self.parameters.shear_modulus
    }

    fn density(&self) -> f64 {
        self.density
    }

    fn initial_state(&self, temperature: f64) -> MaterialState {
        RhtMaterial::initial_state(self, temperature)
    }

    fn kinematic_strain_bound(&self) -> Option<f64> {
        self.kinematic_failure().kinematic_strain_bound()
    }

    fn kinematic_flags(&self, principal_strains: [f64; 3]) -> StateFlags {
        self.kinematic_failure().kinematic_flags(principal_strains)
    }

    fn update(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
    ) -> Result<StepOutput, UpdateError> {
        update(self, state, input)
    }

    fn update_with_tangent(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
        tangent: &mut Matrix6,
    ) -> Result<StepOutput, UpdateError> {
        update_with_tangent(self, state, input, tangent)
    }
}
