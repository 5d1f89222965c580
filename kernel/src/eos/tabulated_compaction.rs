//! Tabulated compaction EoS (LS-DYNA `*EOS_TABULATED_COMPACTION`, EOS type 8) without the
//! energy term:
//!
//! ```text
//! eps = -ln V = ln(1 + mu)                (volumetric strain, positive in compression)
//! h   = max(eps over the history)         (the EoS history variable, starts at 0)
//! eps >= h (loading):            p = C(eps)                    and h <- eps
//! eps <  h (unloading/reloading): p = C(h) + K(h) (eps - h)
//! ```
//!
//! `C` is the piecewise-linear loading curve through the tabulated points `(eps_i, p_i)`,
//! `K` the piecewise-linear interpolation of the tabulated unloading bulk moduli
//! `K_i = dp/d eps` (LS-DYNA's `KU` column). Unloading and reloading follow the same straight
//! line of slope `K(h)` until the previous maximum `h` is reached, then the loading curve
//! again. Beyond the last point `C` is extended with the last segment's slope and `K` is held
//! at its last value; the first point must be the reference state `eps = 0`. LS-DYNA's energy
//! term `gamma T(eps) E` is not included (seed 001 table 5.2, the data set shipped here, gives
//! none): the pressure does not depend on `E`.
//!
//! The derivative returned in [`EnergyLinearPressure::d_base_d_mu`] is taken at the updated
//! (frozen) history, i.e. the elastic unloading stiffness `K(h)/(1 + mu)`, not the loading
//! slope: the bulk sound speed, and so the host's time step, must follow the fastest (elastic)
//! wave, as in LS-DYNA.

use super::EnergyLinearPressure;
use crate::error::{check, ParameterError};
use crate::math::ln;

/// Largest number of points in a [`TabulatedCompaction`] curve (LS-DYNA allows 10).
pub const MAX_COMPACTION_POINTS: usize = 16;

/// One point of the loading curve.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct CompactionPoint {
    /// Volumetric strain `eps = -ln V` (-), positive in compression.
    pub volumetric_strain: f64,
    /// Loading pressure `C(eps)` (Pa).
    pub pressure: f64,
    /// Unloading bulk modulus `K = dp/d eps` (Pa).
    pub unloading_bulk_modulus: f64,
}

impl CompactionPoint {
    const ZERO: CompactionPoint = CompactionPoint {
        volumetric_strain: 0.0,
        pressure: 0.0,
        unloading_bulk_modulus: 0.0,
    };

    /// A point from `eps`, `p` and `K`.
    pub const fn new(volumetric_strain: f64, pressure: f64, unloading_bulk_modulus: f64) -> Self {
        Self {
            volumetric_strain,
            pressure,
            unloading_bulk_modulus,
        }
    }
}

/// Tabulated compaction curve: 2 to [`MAX_COMPACTION_POINTS`] points in a fixed array.
/// Built with [`TabulatedCompaction::new`] (checked) so that the count is always in range.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct TabulatedCompaction {
    points: [CompactionPoint; MAX_COMPACTION_POINTS],
    count: usize,
}

impl TabulatedCompaction {
    /// High-performance concrete for the RC-beam drop-weight test, K&C model input: seed 001
    /// (FOI-R--0281--SE, Hansson, Skoglund & Unosson 2001), table 5.2 "Tabulated equation of
    /// state with loading and unloading bulk modulus". The table's volumetric-strain column
    /// (`ln V`, printed negative) is negated; MPa and GPa converted to Pa. The same numbers,
    /// with every column of the table, are in `fixtures/eos/concrete_table_5_2.csv`.
    pub const CONCRETE_FOI_TABLE_5_2: TabulatedCompaction = TabulatedCompaction::from_points(&[
        CompactionPoint::new(0.0, 0.0, 21.57e9),
        CompactionPoint::new(0.0006, 13.3e6, 21.57e9),
        CompactionPoint::new(0.0022, 33.3e6, 15.15e9),
        CompactionPoint::new(0.0104, 90.0e6, 10.0e9),
        CompactionPoint::new(0.0289, 216.0e6, 18.0e9),
        CompactionPoint::new(0.0510, 390.0e6, 21.0e9),
        CompactionPoint::new(0.0628, 565.0e6, 23.0e9),
        CompactionPoint::new(0.0726, 737.0e6, 25.0e9),
    ]);

    /// Copy `points` (length in `2..=MAX_COMPACTION_POINTS`, checked at compile time for
    /// constants) into the fixed array; unused slots are zero.
    const fn from_points(points: &[CompactionPoint]) -> Self {
        assert!(points.len() >= 2 && points.len() <= MAX_COMPACTION_POINTS);
        let mut array = [CompactionPoint::ZERO; MAX_COMPACTION_POINTS];
        let mut i = 0;
        while i < points.len() {
            array[i] = points[i];
            i += 1;
        }
        Self {
            points: array,
            count: points.len(),
        }
    }

    /// A validated curve from 2 to [`MAX_COMPACTION_POINTS`] points.
    pub fn new(points: &[CompactionPoint]) -> Result<Self, ParameterError> {
        if points.len() < 2 || points.len() > MAX_COMPACTION_POINTS {
            return Err(ParameterError::OutOfRange {
                field: "points",
                value: points.len() as f64,
                min: 2.0,
                max: MAX_COMPACTION_POINTS as f64,
            });
        }
        let table = Self::from_points(points);
        table.validate()?;
        Ok(table)
    }

    /// The tabulated points.
    pub fn points(&self) -> &[CompactionPoint] {
        &self.points[..self.count]
    }

    /// Index `i` of the segment `[eps_i, eps_{i+1}]` used at `eps`: the last `i` with
    /// `eps_i <= eps`, limited to `0..=count-2` (so the end segments extrapolate).
    fn segment(&self, strain: f64) -> usize {
        let points = self.points();
        let mut i = 0;
        while i + 2 < points.len() && points[i + 1].volumetric_strain <= strain {
            i += 1;
        }
        i
    }

    /// Loading curve `C(eps)` and its slope. Exactly `p_i` at `eps = eps_i` (the point is
    /// always the left end of its segment, or the anchor of the extrapolation beyond the
    /// last point).
    pub fn loading_pressure(&self, strain: f64) -> (f64, f64) {
        let points = self.points();
        let last = points[points.len() - 1];
        let i = self.segment(strain);
        let left = points[i];
        let right = points[i + 1];
        let slope =
            (right.pressure - left.pressure) / (right.volumetric_strain - left.volumetric_strain);
        if strain >= last.volumetric_strain {
            (
                last.pressure + slope * (strain - last.volumetric_strain),
                slope,
            )
        } else {
            let fraction = (strain - left.volumetric_strain)
                / (right.volumetric_strain - left.volumetric_strain);
            (
                left.pressure + (right.pressure - left.pressure) * fraction,
                slope,
            )
        }
    }

    /// Unloading bulk modulus `K(eps)`: linear between points, constant beyond the ends.
    pub fn unloading_bulk_modulus(&self, strain: f64) -> f64 {
        let points = self.points();
        let first = points[0];
        let last = points[points.len() - 1];
        if strain <= first.volumetric_strain {
            return first.unloading_bulk_modulus;
        }
        if strain >= last.volumetric_strain {
            return last.unloading_bulk_modulus;
        }
        let i = self.segment(strain);
        let left = points[i];
        let right = points[i + 1];
        let fraction =
            (strain - left.volumetric_strain) / (right.volumetric_strain - left.volumetric_strain);
        left.unloading_bulk_modulus
            + (right.unloading_bulk_modulus - left.unloading_bulk_modulus) * fraction
    }

    /// Pressure at volumetric strain `eps` given the maximum strain `history` reached so far:
    /// returns `(p, K at the new maximum, new maximum)`.
    pub fn evaluate_strain(&self, strain: f64, history: f64) -> (f64, f64, f64) {
        if strain >= history {
            let (pressure, _) = self.loading_pressure(strain);
            (pressure, self.unloading_bulk_modulus(strain), strain)
        } else {
            let (peak, _) = self.loading_pressure(history);
            let modulus = self.unloading_bulk_modulus(history);
            (peak + modulus * (strain - history), modulus, history)
        }
    }

    /// Energy-linear terms at compression `mu` (`eps = ln(1 + mu)`) and the updated maximum
    /// strain. `dp/dmu = K(h)/(1 + mu)` (frozen history, see the module docs); no energy term.
    pub fn evaluate(&self, mu: f64, history: f64) -> (EnergyLinearPressure, f64) {
        let one_plus = 1.0 + mu;
        let strain = ln(one_plus);
        let (pressure, modulus, history) = self.evaluate_strain(strain, history);
        (
            EnergyLinearPressure {
                base: pressure,
                d_base_d_mu: modulus / one_plus,
                energy_coefficient: 0.0,
                d_energy_coefficient_d_mu: 0.0,
            },
            history,
        )
    }

    /// 2 to 16 points; the first at `eps = 0`; strains strictly increasing; pressures finite
    /// and non-decreasing; unloading moduli `> 0`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        if self.count < 2 || self.count > MAX_COMPACTION_POINTS {
            return Err(ParameterError::OutOfRange {
                field: "points",
                value: self.count as f64,
                min: 2.0,
                max: MAX_COMPACTION_POINTS as f64,
            });
        }
        let points = self.points();
        check::range("volumetric_strain", points[0].volumetric_strain, 0.0, 0.0)?;
        for (i, point) in points.iter().enumerate() {
            check::finite("volumetric_strain", point.volumetric_strain)?;
            check::finite("pressure", point.pressure)?;
            check::positive("unloading_bulk_modulus", point.unloading_bulk_modulus)?;
            if i > 0 {
                let previous = points[i - 1];
                if point.volumetric_strain <= previous.volumetric_strain {
                    return Err(ParameterError::Inconsistent {
                        field: "volumetric_strain",
                        other: "previous volumetric_strain",
                    });
                }
                if point.pressure < previous.pressure {
                    return Err(ParameterError::Inconsistent {
                        field: "pressure",
                        other: "previous pressure",
                    });
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eos::Eos;
    use crate::math::exp;
    use std::vec::Vec;

    const TABLE: TabulatedCompaction = TabulatedCompaction::CONCRETE_FOI_TABLE_5_2;

    /// Parse `fixtures/eos/concrete_table_5_2.csv` into `(eps, p, K)` in SI. Numbers are
    /// re-parsed with their unit exponent appended (`"13.3" -> "13.3e6"`) so that the result
    /// is the same double as the literal in the constant.
    fn fixture_points() -> Vec<(f64, f64, f64)> {
        let text = include_str!("../../../fixtures/eos/concrete_table_5_2.csv");
        let mut rows = Vec::new();
        for line in text.lines() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') || line.starts_with("density") {
                continue;
            }
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            assert_eq!(fields.len(), 5, "row {line}");
            let strain: f64 = fields[2].parse().unwrap();
            let pressure: f64 = std::format!("{}e6", fields[3]).parse().unwrap();
            let modulus: f64 = std::format!("{}e9", fields[4]).parse().unwrap();
            // `0.0 - x` rather than `-x`: the first row must give +0.0, not -0.0.
            rows.push((0.0 - strain, pressure, modulus));
        }
        rows
    }

    #[test]
    fn constant_matches_the_fixture_file() {
        // GOAL: the shipped constant is the data set in fixtures/eos/concrete_table_5_2.csv.
        // SETUP: parse the CSV (seed 001 table 5.2 as printed).
        // REFERENCE: the fixture; tolerance: bit-for-bit.
        let rows = fixture_points();
        let points = TABLE.points();
        assert_eq!(rows.len(), points.len());
        for (row, point) in rows.iter().zip(points) {
            assert_eq!(row.0.to_bits(), point.volumetric_strain.to_bits());
            assert_eq!(row.1.to_bits(), point.pressure.to_bits());
            assert_eq!(row.2.to_bits(), point.unloading_bulk_modulus.to_bits());
        }
        assert_eq!(TABLE.validate(), Ok(()));
    }

    #[test]
    fn reproduces_every_table_point_exactly() {
        // GOAL: the loading curve passes through every tabulated point.
        // SETUP: virgin material (history 0), loading to each tabulated strain.
        // REFERENCE: table 5.2 pressures; tolerance: bit-for-bit at the tabulated strain,
        //   1e-12 relative through Eos::evaluate with mu = exp(eps) - 1 (the round trip
        //   eps -> mu -> ln(1 + mu) is not exact in floating point).
        for point in TABLE.points() {
            let (p, _, history) = TABLE.evaluate_strain(point.volumetric_strain, 0.0);
            assert_eq!(
                p.to_bits(),
                point.pressure.to_bits(),
                "eps {}",
                point.volumetric_strain
            );
            assert_eq!(history, point.volumetric_strain);
            let mu = exp(point.volumetric_strain) - 1.0;
            let (terms, _) = Eos::from(TABLE).evaluate(mu, 0.0);
            let error = (terms.base - point.pressure).abs();
            assert!(
                error <= 1e-12 * point.pressure.abs() + 1e-6,
                "eps {}",
                point.volumetric_strain
            );
        }
    }

    #[test]
    fn unloading_is_linear_with_the_interpolated_unloading_modulus() {
        // GOAL: below the maximum strain the pressure is the straight line of slope K(h).
        // SETUP: load to h = 0.04 (between table points 0.0289 and 0.0510), unload to
        //   eps = 0.035, 0.02, 0.0.
        // REFERENCE: K(h) = 18 + (21 - 18)(0.04 - 0.0289)/(0.0510 - 0.0289) GPa,
        //   p = C(h) + K(h)(eps - h); history unchanged; tolerance 1e-12 relative.
        let h = 0.04;
        let (peak, _, history) = TABLE.evaluate_strain(h, 0.0);
        assert_eq!(history, h);
        let modulus = 18.0e9 + 3.0e9 * (h - 0.0289) / (0.0510 - 0.0289);
        assert!((TABLE.unloading_bulk_modulus(h) / modulus - 1.0).abs() < 1e-12);
        for eps in [0.035, 0.02, 0.0] {
            let (p, k, new_history) = TABLE.evaluate_strain(eps, history);
            assert_eq!(new_history, h);
            assert!((k / modulus - 1.0).abs() < 1e-12);
            let expected = peak + modulus * (eps - h);
            assert!(((p - expected) / peak).abs() < 1e-12, "eps {eps}");
        }
        // Unloading is stiffer than the loading curve there, so there is a permanent
        // volumetric strain at zero pressure.
        let residual = h - peak / modulus;
        assert!(residual > 0.0);
        let (p, _, _) = TABLE.evaluate_strain(residual, history);
        assert!(p.abs() < 1e-6 * peak);
    }

    #[test]
    fn reloading_returns_to_the_loading_curve() {
        // GOAL: reloading follows the unloading line back to h, then the loading curve.
        // SETUP: load to h = 0.04, unload to 0.03, reload to 0.04 and on to 0.06.
        // REFERENCE: p(h) on reloading = C(h) (line and curve meet); beyond h, p = C(eps)
        //   and the history grows; tolerance 1e-12 relative.
        let h = 0.04;
        let (peak, _, history) = TABLE.evaluate_strain(h, 0.0);
        let (_, _, history) = TABLE.evaluate_strain(0.03, history);
        let (back, _, same) = TABLE.evaluate_strain(h, history);
        assert_eq!(same, h);
        assert!(((back - peak) / peak).abs() < 1e-12);
        let (p, _, grown) = TABLE.evaluate_strain(0.06, history);
        let (curve, _) = TABLE.loading_pressure(0.06);
        assert_eq!(p, curve);
        assert_eq!(grown, 0.06);
        let expected = 390.0e6 + (565.0e6 - 390.0e6) * (0.06 - 0.0510) / (0.0628 - 0.0510);
        assert!(((p - expected) / expected).abs() < 1e-12);
    }

    #[test]
    fn terms_through_eos_carry_the_history_and_the_elastic_stiffness() {
        // GOAL: Eos::evaluate updates the maximum strain and reports dp/dmu = K(h)/(1 + mu).
        // SETUP: mu = 0.03 from virgin state, then mu = 0.01 (unloading).
        // REFERENCE: h = ln(1.03); K(h)/(1.01) on unloading; tolerance 1e-12 relative.
        let eos = Eos::from(TABLE);
        assert_eq!(eos.initial_history(), 0.0);
        let (_, history) = eos.evaluate(0.03, eos.initial_history());
        assert_eq!(history, ln(1.03));
        let (terms, same) = eos.evaluate(0.01, history);
        assert_eq!(same, history);
        let expected = TABLE.unloading_bulk_modulus(history) / 1.01;
        assert!((terms.d_base_d_mu / expected - 1.0).abs() < 1e-12);
        assert_eq!(terms.energy_coefficient, 0.0);
        // Tension from the virgin state follows the first unloading modulus.
        let (terms, _) = eos.evaluate(-0.001, 0.0);
        assert!((terms.base / (21.57e9 * ln(0.999)) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bad_tables_give_typed_errors() {
        // GOAL: invalid curves are rejected with typed errors.
        // SETUP: too few/many points, first strain not 0, unsorted strains, decreasing
        //   pressure, non-positive modulus, NaN. REFERENCE: ParameterError variants.
        let ok = [
            CompactionPoint::new(0.0, 0.0, 10e9),
            CompactionPoint::new(0.01, 50e6, 12e9),
        ];
        assert!(TabulatedCompaction::new(&ok).is_ok());
        assert!(matches!(
            TabulatedCompaction::new(&ok[..1]),
            Err(ParameterError::OutOfRange {
                field: "points",
                ..
            })
        ));
        let many = [ok[0]; MAX_COMPACTION_POINTS + 1];
        assert!(matches!(
            TabulatedCompaction::new(&many),
            Err(ParameterError::OutOfRange {
                field: "points",
                ..
            })
        ));
        let mut bad = ok;
        bad[0].volumetric_strain = 0.001;
        assert!(matches!(
            TabulatedCompaction::new(&bad),
            Err(ParameterError::OutOfRange {
                field: "volumetric_strain",
                ..
            })
        ));
        let mut bad = ok;
        bad[1].volumetric_strain = 0.0;
        assert_eq!(
            TabulatedCompaction::new(&bad),
            Err(ParameterError::Inconsistent {
                field: "volumetric_strain",
                other: "previous volumetric_strain"
            })
        );
        let mut bad = ok;
        bad[1].pressure = -1.0;
        assert_eq!(
            TabulatedCompaction::new(&bad),
            Err(ParameterError::Inconsistent {
                field: "pressure",
                other: "previous pressure"
            })
        );
        let mut bad = ok;
        bad[1].unloading_bulk_modulus = 0.0;
        assert_eq!(
            TabulatedCompaction::new(&bad),
            Err(ParameterError::NotPositive {
                field: "unloading_bulk_modulus",
                value: 0.0
            })
        );
        let mut bad = ok;
        bad[1].pressure = f64::NAN;
        assert_eq!(
            TabulatedCompaction::new(&bad),
            Err(ParameterError::NotFinite { field: "pressure" })
        );
    }
}
