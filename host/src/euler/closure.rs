//! The mixed-cell closure: how a cell's volume change over a Lagrange step is shared among
//! the phases it holds.
//!
//! stoss shares it by **equal pressure increments** among the materials, with **void first**:
//!
//! - Void has no stiffness, so in compression it closes before any material is squeezed
//!   (CTH's rule, McGlaun et al. 1990): the cell's volume loss goes to the void up to its
//!   volume, and only the rest to the materials.
//! - Between materials, each takes a share proportional to its volume over its stiffness,
//!   `dV_k = dV (V_k / K_k) / sum_j (V_j / K_j)` with `K_k = rho_k c_k^2` (the material's
//!   longitudinal modulus from its last wave speed): to first order every material's pressure
//!   then changes by the same amount, so a stiff rod and a softer target in one cell do not
//!   trade volume at equal strain (the closure Benson 1992 sec. 4.3 calls "equal pressure
//!   increment"; Miller & Puckett 1996 compare it with full pressure relaxation). Equal
//!   volumetric strain, the simplest closure, would give a cell of tungsten and steel the
//!   same strain and hence pressures 1.8 times apart; full relaxation to one pressure needs
//!   an iteration through every material's EoS per cell and step.
//! - In expansion with void present (a free surface or the crater wall), a material under
//!   pressure expands towards zero pressure, `dV_k <= V_k p_k / K_k`, and the void opens for
//!   the rest: material next to void cannot be pulled into tension by it.
//!
//! - **Void insertion** (tensile failure, CTH's fracture model, McGlaun et al. 1990): a
//!   material with a fracture pressure `p_f < 0` whose pressure would fall below it over the
//!   step, `p_k - K_k dV_k / V_k < p_f`, does not stretch: it takes the volume change that
//!   returns it to zero pressure to first order, `dV_k = V_k p_k / B_k` with its bulk modulus
//!   `B_k`, and void is inserted for the rest of the cell's change. From then on the void beside
//!   it keeps it from being pulled into tension (the rule above) until the cell closes again.
//!
//! Materials below [`super::ACTIVE_FRACTION`] of the cell take no share (their state is
//! carried unchanged).

use super::MAX_PHASES;

/// Void below this fraction of the cell does not let the materials beside it relax in
/// expansion: it is round-off left by the remap (a full cell's phases sum to its volume only
/// to round-off), not a free surface, and material there is strained as in a pure cell.
pub const VOID_FRACTION: f64 = 1e-6;

/// One phase of a cell as the closure sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phase {
    /// Current volume.
    pub volume: f64,
    /// Longitudinal modulus `rho c^2` (Pa); ignored for void.
    pub stiffness: f64,
    /// Pressure (Pa); ignored for void.
    pub pressure: f64,
    /// `true` if the phase takes part (an active material, or void with volume).
    pub active: bool,
    /// Bulk modulus `rho c^2 - 4G/3` (Pa), for the return to zero pressure of a fractured
    /// material; ignored for void.
    pub bulk_modulus: f64,
    /// Fracture pressure (Pa, negative): below it void is inserted; `-inf` for a material that
    /// never fractures, and for void.
    pub fracture_pressure: f64,
}

impl Default for Phase {
    fn default() -> Self {
        Phase {
            volume: 0.0,
            stiffness: 0.0,
            pressure: 0.0,
            active: false,
            bulk_modulus: 0.0,
            fracture_pressure: f64::NEG_INFINITY,
        }
    }
}

/// Share the cell's volume change `change` among `phases` (void last): returns each phase's
/// volume change; they sum to `change` (to round-off) unless no phase can take it. A material
/// the shares would pull below its fracture pressure returns to zero pressure instead, and
/// void is inserted for the difference.
pub fn share(change: f64, phases: &[Phase; MAX_PHASES], materials: usize) -> [f64; MAX_PHASES] {
    let void = MAX_PHASES - 1;
    let mut out = closure_share(change, phases, materials);
    let mut fractured = false;
    for k in 0..materials {
        let phase = &phases[k];
        if !phase.active || phase.stiffness <= 0.0 || phase.volume <= 0.0 {
            continue;
        }
        let predicted = phase.pressure - phase.stiffness * out[k] / phase.volume;
        if predicted < phase.fracture_pressure && phase.bulk_modulus > 0.0 {
            out[k] = phase.volume * phase.pressure / phase.bulk_modulus;
            fractured = true;
        }
    }
    if fractured {
        let materials_change: f64 = out[..materials].iter().sum();
        out[void] = change - materials_change;
    }
    out
}

/// The shares without fracture: void first, equal pressure increments, relaxation beside void.
fn closure_share(change: f64, phases: &[Phase; MAX_PHASES], materials: usize) -> [f64; MAX_PHASES] {
    let void = MAX_PHASES - 1;
    let mut out = [0.0; MAX_PHASES];
    let void_volume = phases[void].volume.max(0.0);
    let mut weights = [0.0; MAX_PHASES];
    let mut weight_sum = 0.0;
    for k in 0..materials {
        if phases[k].active && phases[k].stiffness > 0.0 {
            weights[k] = phases[k].volume / phases[k].stiffness;
            weight_sum += weights[k];
        }
    }
    if weight_sum == 0.0 {
        out[void] = change;
        return out;
    }
    if change <= 0.0 {
        let closed = (-change).min(void_volume);
        out[void] = -closed;
        let rest = change + closed;
        for k in 0..materials {
            out[k] = rest * weights[k] / weight_sum;
        }
        return out;
    }
    let total: f64 = phases.iter().map(|p| p.volume.max(0.0)).sum();
    if void_volume <= VOID_FRACTION * total {
        for k in 0..materials {
            out[k] = change * weights[k] / weight_sum;
        }
        return out;
    }
    let mut taken = 0.0;
    for k in 0..materials {
        if weights[k] > 0.0 {
            let relaxed = (phases[k].volume * phases[k].pressure / phases[k].stiffness).max(0.0);
            out[k] = (change * weights[k] / weight_sum).min(relaxed);
            taken += out[k];
        }
    }
    out[void] = change - taken;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn phase(volume: f64, stiffness: f64, pressure: f64) -> Phase {
        Phase {
            volume,
            stiffness,
            pressure,
            active: true,
            bulk_modulus: stiffness,
            fracture_pressure: f64::NEG_INFINITY,
        }
    }

    #[test]
    fn void_closes_first_and_materials_share_by_compliance() {
        // GOAL: compression closes void first, then equal pressure increments.
        let phases = [
            phase(1.0, 4.0, 0.0),
            phase(1.0, 1.0, 0.0),
            Phase::default(),
            phase(0.1, 0.0, 0.0),
        ];
        let out = share(-0.6, &phases, 3);
        assert!((out[3] + 0.1).abs() < 1e-15);
        // -0.5 shared 1/4 : 1 -> -0.1 and -0.4; pressure increments K dV/V equal.
        assert!((out[0] + 0.1).abs() < 1e-15 && (out[1] + 0.4).abs() < 1e-15);
        assert!((4.0 * out[0] - out[1]).abs() < 1e-15);
        assert!((out.iter().sum::<f64>() + 0.6).abs() < 1e-15);
    }

    #[test]
    fn next_to_void_a_material_expands_only_to_zero_pressure() {
        let phases = [
            phase(1.0, 10.0, 1.0),
            Phase::default(),
            Phase::default(),
            phase(0.5, 0.0, 0.0),
        ];
        let out = share(0.3, &phases, 3);
        assert!((out[0] - 0.1).abs() < 1e-15 && (out[3] - 0.2).abs() < 1e-15);
        // In tension it does not expand at all.
        let tense = [
            phase(1.0, 10.0, -1.0),
            Phase::default(),
            Phase::default(),
            phase(0.5, 0.0, 0.0),
        ];
        let out = share(0.3, &tense, 3);
        assert_eq!(out[0], 0.0);
        assert_eq!(out[3], 0.3);
    }

    #[test]
    fn round_off_void_does_not_free_a_material_in_tension() {
        // GOAL: void a remap leaves by round-off (below VOID_FRACTION of the cell) is not a
        // free surface: a material in tension beside it is strained as in a pure cell (a
        // seed of 1e-12 void must not grow into a cavity under every release wave).
        let phases = [
            phase(1.0, 10.0, -1.0),
            Phase::default(),
            Phase::default(),
            phase(1e-12, 0.0, 0.0),
        ];
        let out = share(0.3, &phases, 3);
        assert_eq!(out[0], 0.3);
        assert_eq!(out[3], 0.0);
        // Just above the fraction, it is a free surface again.
        let phases = [
            phase(1.0, 10.0, -1.0),
            Phase::default(),
            Phase::default(),
            phase(2.0 * VOID_FRACTION, 0.0, 0.0),
        ];
        assert_eq!(share(0.3, &phases, 3)[3], 0.3);
    }

    #[test]
    fn a_material_pulled_past_its_fracture_pressure_returns_to_zero_and_void_opens() {
        // GOAL: void insertion: a full cell stretched past a material's fracture pressure
        //       inserts void so the material returns to zero pressure; short of it, nothing
        //       changes. REFERENCE: dV = V p / B (first order), the rest void.
        let fracturing = |pressure: f64| Phase {
            fracture_pressure: -1.0,
            bulk_modulus: 6.0,
            ..phase(1.0, 10.0, pressure)
        };
        let full = [
            fracturing(-0.5),
            Phase::default(),
            Phase::default(),
            Phase::default(),
        ];
        // Stretched by 0.04: predicted -0.5 - 10 * 0.04 = -0.9, above -1: as before.
        let out = share(0.04, &full, 3);
        assert_eq!(out[0], 0.04);
        assert_eq!(out[3], 0.0);
        // Stretched by 0.06: -1.1, past -1: the material returns to zero pressure.
        let out = share(0.06, &full, 3);
        assert!((out[0] - (-0.5 / 6.0)).abs() < 1e-15);
        assert!((out[0] + out[3] - 0.06).abs() < 1e-15);
        assert!(out[3] > 0.06);
        // A material without a fracture pressure stretches as before.
        let strong = [
            phase(1.0, 10.0, -0.5),
            Phase::default(),
            Phase::default(),
            Phase::default(),
        ];
        assert_eq!(share(0.06, &strong, 3)[0], 0.06);
    }
}
