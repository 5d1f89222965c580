//! The two fluids of a blast calculation, detonation products (JWL) and air (ideal gas),
//! as one Mie-Grüneisen mixture carried by the products' mass fraction `Y`.
//!
//! Both are Mie-Grüneisen: `p = f(rho) + Gamma rho e` with `e` the specific internal energy.
//! - JWL (Lee, Hornig & Kury 1968): `f = A(1 - w/(R1 V))exp(-R1 V) + B(1 - w/(R2 V))exp(-R2 V)`
//!   with `V = rho0/rho`, and `Gamma = w` (the kernel's [`Jwl`] with `E = rho0 e`).
//! - Air: `f = 0`, `Gamma = gamma - 1`.
//!
//! A cell holding both is closed with the mixture rule of the Mie-Grüneisen multi-fluid
//! schemes (Shyue 2001, *J. Comput. Phys.* 171, 678):
//! `rho e = p sum_k phi_k / Gamma_k - sum_k phi_k f_k / Gamma_k`, with the products' mass fraction
//! `Y` standing in for the volume fraction `phi`. It is exact in pure cells. In a mixed cell it
//! evaluates the JWL cold term at the cell density rather than the products' own density: a
//! simplification of a true two-material interface, confined to the cells of the contact
//! surface between products and air.
//!
//! Programmed burn multiplies the pressure (and the squared sound speed) of a cell of the
//! charge by its burn fraction `F` in `[0, 1]` (LS-DYNA `*MAT_HIGH_EXPLOSIVE_BURN`).

use stoss_kernel::eos::Jwl;

/// Detonation products and air.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fluids {
    /// The products' JWL constants.
    pub products: Jwl,
    /// The ratio of specific heats of air.
    pub air_gamma: f64,
}

/// Smallest squared sound speed returned (m^2/s^2): keeps the Riemann solver's wave-speed
/// estimates finite in unburned explosive, where the pressure is zero.
const MINIMUM_SOUND_SPEED_SQUARED: f64 = 1.0;

impl Fluids {
    /// JWL cold term `f(rho)` and its derivative `df/drho`.
    fn cold(&self, density: f64) -> (f64, f64) {
        let mu = density / self.products.reference_density - 1.0;
        let terms = self.products.evaluate(mu);
        (
            terms.base,
            terms.d_base_d_mu / self.products.reference_density,
        )
    }

    /// `G(Y) = Y/w + (1 - Y)/(gamma - 1)`, the mixture's `1/Gamma`.
    fn inverse_gruneisen(&self, products_fraction: f64) -> f64 {
        products_fraction / self.products.omega + (1.0 - products_fraction) / (self.air_gamma - 1.0)
    }

    /// The products' share of the cold term and of its density derivative, `Y f(rho)/w` and
    /// `Y f'(rho)/w` (0 without products): one JWL evaluation for every formula below.
    fn cold_terms(&self, density: f64, products_fraction: f64) -> (f64, f64) {
        if products_fraction > 0.0 {
            let (f, slope) = self.cold(density);
            (
                products_fraction * f / self.products.omega,
                products_fraction * slope / self.products.omega,
            )
        } else {
            (0.0, 0.0)
        }
    }

    /// Pressure of the fully burned mixture: `p = (rho e + Y f(rho)/w) / G(Y)`.
    pub fn pressure(&self, density: f64, specific_energy: f64, products_fraction: f64) -> f64 {
        let (cold, _) = self.cold_terms(density, products_fraction);
        self.pressure_with(density, specific_energy, products_fraction, cold)
    }

    /// [`Fluids::pressure`] with the cold term `Y f/w` given.
    fn pressure_with(
        &self,
        density: f64,
        specific_energy: f64,
        products_fraction: f64,
        cold: f64,
    ) -> f64 {
        (density * specific_energy + cold) / self.inverse_gruneisen(products_fraction)
    }

    /// Specific internal energy of the fully burned mixture at pressure `p`: the inverse of
    /// [`Fluids::pressure`], `e = (p G(Y) - Y f(rho)/w) / rho`.
    pub fn specific_energy(&self, density: f64, pressure: f64, products_fraction: f64) -> f64 {
        let (cold, _) = self.cold_terms(density, products_fraction);
        self.specific_energy_with(density, pressure, products_fraction, cold)
    }

    /// [`Fluids::specific_energy`] with the cold term `Y f/w` given.
    fn specific_energy_with(
        &self,
        density: f64,
        pressure: f64,
        products_fraction: f64,
        cold: f64,
    ) -> f64 {
        (pressure * self.inverse_gruneisen(products_fraction) - cold) / density
    }

    /// Squared sound speed of the fully burned mixture,
    /// `c^2 = (dp/drho)_e + p/rho^2 (dp/de)_rho = (e + Y f'(rho)/w + p/rho) / G(Y)`.
    pub fn sound_speed_squared(
        &self,
        density: f64,
        specific_energy: f64,
        pressure: f64,
        products_fraction: f64,
    ) -> f64 {
        let (_, slope) = self.cold_terms(density, products_fraction);
        self.sound_speed_squared_with(density, specific_energy, pressure, products_fraction, slope)
    }

    /// [`Fluids::sound_speed_squared`] with the slope term `Y f'/w` given.
    fn sound_speed_squared_with(
        &self,
        density: f64,
        specific_energy: f64,
        pressure: f64,
        products_fraction: f64,
        slope: f64,
    ) -> f64 {
        let c2 = (specific_energy + slope + pressure / density)
            / self.inverse_gruneisen(products_fraction);
        c2.max(MINIMUM_SOUND_SPEED_SQUARED)
    }

    /// [`Fluids::specific_energy`] at pressure `p` and [`Fluids::sound_speed_squared`] there,
    /// from one JWL evaluation.
    pub fn energy_and_sound_speed_squared(
        &self,
        density: f64,
        pressure: f64,
        products_fraction: f64,
    ) -> (f64, f64) {
        let (cold, slope) = self.cold_terms(density, products_fraction);
        let e = self.specific_energy_with(density, pressure, products_fraction, cold);
        let c2 = self.sound_speed_squared_with(density, e, pressure, products_fraction, slope);
        (e, c2)
    }

    /// Pressure and squared sound speed of a cell at burn fraction `burn`, from one JWL
    /// evaluation.
    pub fn state(
        &self,
        density: f64,
        specific_energy: f64,
        products_fraction: f64,
        burn: f64,
    ) -> (f64, f64) {
        let (cold, slope) = self.cold_terms(density, products_fraction);
        let p = self.pressure_with(density, specific_energy, products_fraction, cold);
        let c2 =
            self.sound_speed_squared_with(density, specific_energy, p, products_fraction, slope);
        (burn * p, (burn * c2).max(MINIMUM_SOUND_SPEED_SQUARED))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FLUIDS: Fluids = Fluids {
        products: Jwl::C4,
        air_gamma: 1.4,
    };

    /// GOAL: the mixture reduces to each pure fluid's own EoS.
    /// SETUP: Y = 0 (air) and Y = 1 (C4 products) at a few states.
    /// REFERENCE: ideal gas `p = (gamma - 1) rho e`, `c^2 = gamma p/rho`; the kernel's JWL
    /// `p = base(mu) + w (1 + mu) E` with `E = rho0 e`.
    #[test]
    fn pure_cells_are_the_pure_equations_of_state() {
        let (rho, e) = (1.225, 2.068e5);
        let p = FLUIDS.pressure(rho, e, 0.0);
        assert!((p - 0.4 * rho * e).abs() < 1e-9 * p);
        let c2 = FLUIDS.sound_speed_squared(rho, e, p, 0.0);
        assert!((c2 - 1.4 * p / rho).abs() < 1e-9 * c2);
        for (rho, e) in [(1601.0, 5.6e6), (2200.0, 4.0e6), (100.0, 1.0e6)] {
            let mu = rho / 1601.0 - 1.0;
            let terms = Jwl::C4.evaluate(mu);
            let expected = terms.base + terms.energy_coefficient * 1601.0 * e;
            let p = FLUIDS.pressure(rho, e, 1.0);
            assert!((p - expected).abs() < 1e-9 * expected.abs());
            assert!((FLUIDS.specific_energy(rho, p, 1.0) - e).abs() < 1e-9 * e);
        }
    }

    /// GOAL: the sound speed is the isentropic derivative of the pressure.
    /// SETUP: C4 products and a 50/50 mixture; central differences along an isentrope
    /// (`de = p/rho^2 drho`).
    /// REFERENCE: `c^2 = (dp/drho)_s`.
    #[test]
    fn sound_speed_is_the_isentropic_derivative() {
        for y in [1.0, 0.5] {
            let (rho, e) = (1800.0, 5.0e6);
            let p = FLUIDS.pressure(rho, e, y);
            let h = 1e-4 * rho;
            let de = p / (rho * rho) * h;
            let dp = FLUIDS.pressure(rho + h, e + de, y) - FLUIDS.pressure(rho - h, e - de, y);
            let numeric = dp / (2.0 * h);
            let c2 = FLUIDS.sound_speed_squared(rho, e, p, y);
            assert!((c2 - numeric).abs() < 1e-5 * c2, "Y {y}: {c2} vs {numeric}");
        }
    }
}
