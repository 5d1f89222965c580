//! Kolsky analysis of split Hopkinson (compression) bar gauges (Kolsky 1949; Gray 2000, ASM
//! Handbook vol. 8, "Classic split-Hopkinson pressure bar testing"), the same for the gauges
//! the FE bar model writes ([`super::ShpbSpec::run`]) and for a real bar's recorded ones
//! ([`analyse_recorded`], `stoss analyse-shpb`).
//!
//! With `c0 = sqrt(E/rho)`, bar area `A_b`, specimen initial area `A_s` and length `l_s`, and
//! bar strains compressive positive, the waves at the specimen faces at time `t` follow from
//! the gauges by time shifts at `c0` (wave separation; dispersion is not corrected):
//!
//! ```text
//! eps_I(t) = g_i(t - d_i/c0)      while t - d_i/c0 < L_i/c0 + d_i/c0   (before the reflection arrives)
//! eps_R(t) = g_i(t + d_i/c0)      for   t >= L_i/c0                     (after it is born)
//! eps_T(t) = g_t(t + d_t/c0)
//! ```
//!
//! Face velocities `v_1 = c0 (eps_I - eps_R)`, `v_2 = c0 eps_T`; face forces
//! `F_1 = E A_b (eps_I + eps_R)`, `F_2 = E A_b eps_T`. Engineering stress and strain rate:
//!
//! | analysis | stress | strain rate |
//! |---|---|---|
//! | `1-wave` | `E (A_b/A_s) eps_T` (back face) | `-2 c0 eps_R / l_s` |
//! | `2-wave` | `E (A_b/A_s) (eps_I + eps_R)` (front face) | `-2 c0 eps_R / l_s` |
//! | `3-wave` | `E (A_b/A_s) (eps_I + eps_R + eps_T) / 2` (mean) | `c0 (eps_I - eps_R - eps_T) / l_s` |
//!
//! The 1- and 2-wave strain rates assume equilibrium (`eps_I + eps_R = eps_T`); the 3-wave
//! rate does not. The engineering strain is the time integral of the rate (trapezoidal, from
//! before the pulse arrives). The analysis runs on a uniform 0.1 us grid over
//! `[t_a - 2 us, t_a + T + rise + 5 us]`, `t_a` the time the incident pulse reaches the
//! specimen (`L_i/c0` in the FE model). The stress-strain curve is its loading
//! branch: up to the largest strain, strictly increasing strains only; recorded points past
//! the largest strain get the last stress. The mean strain rate is
//! `0.8 eps_max / (t(0.9 eps_max) - t(0.1 eps_max))`.
//!
//! The wave separation needs the pulses not to overlap at the gauges:
//! `T + rise <= 2 d_i / c0`, `<= 2 (L_i - d_i) / c0` and `<= 2 (L_t - d_t) / c0`; the spec is
//! rejected otherwise.
//!
//! # Recorded gauges
//!
//! A real bar's signals carry no clock of the pulse: [`analyse_recorded`] finds the incident
//! pulse on the incident gauge as the span where the signal exceeds 5 % of its largest value
//! (the start back-extrapolated along the rising edge to zero, the end likewise along the
//! falling edge), so that `t_a = t_start + d_i / c0` and `T + rise` is the span. Strains are
//! compressive positive, as the FE gauges; a bar with tensile-positive bridges is read with
//! the sign flipped (`--tension-positive`). Dispersion is not corrected (Pochhammer-Chree
//! correction is not built): keep the analysis for pulses whose rise time is long against
//! the bar's radius over `c0`.

use super::{Analysis, SAMPLING};
use crate::measure::interpolate;

/// Engineering stress-strain of the specimen by one analysis, on the analysis time grid.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StressStrain {
    /// Time at the specimen faces (s).
    pub time: Vec<f64>,
    /// Engineering strain (compressive positive).
    pub strain: Vec<f64>,
    /// Engineering strain rate (1/s).
    pub strain_rate: Vec<f64>,
    /// Engineering stress (Pa, compressive positive).
    pub stress: Vec<f64>,
}

impl StressStrain {
    /// The loading branch `(strain, stress)`: up to the largest strain, strictly increasing
    /// strains only.
    pub fn curve(&self) -> Vec<(f64, f64)> {
        let last = self
            .strain
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |best, (k, &e)| {
                if e > best.1 {
                    (k, e)
                } else {
                    best
                }
            })
            .0;
        let mut curve: Vec<(f64, f64)> = Vec::with_capacity(last + 1);
        for k in 0..=last.min(self.strain.len().saturating_sub(1)) {
            if curve.last().is_none_or(|p| self.strain[k] > p.0) {
                curve.push((self.strain[k], self.stress[k]));
            }
        }
        curve
    }

    /// Largest engineering strain.
    pub fn max_strain(&self) -> f64 {
        self.strain.iter().copied().fold(0.0, f64::max)
    }

    /// Mean strain rate `0.8 eps_max / (t(0.9 eps_max) - t(0.1 eps_max))` (1/s).
    pub fn mean_strain_rate(&self) -> f64 {
        let max = self.max_strain();
        let crossing = |level: f64| {
            let k = self.strain.iter().position(|&e| e >= level)?;
            if k == 0 {
                return Some(self.time[0]);
            }
            let (e0, e1) = (self.strain[k - 1], self.strain[k]);
            let f = if e1 > e0 {
                (level - e0) / (e1 - e0)
            } else {
                1.0
            };
            Some(self.time[k - 1] + f * (self.time[k] - self.time[k - 1]))
        };
        match (crossing(0.1 * max), crossing(0.9 * max)) {
            (Some(t1), Some(t2)) if t2 > t1 => 0.8 * max / (t2 - t1),
            _ => f64::NAN,
        }
    }
}

/// The separated bar waves at the specimen faces (compressive positive strains).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BarWaves {
    /// Time at the specimen faces (s).
    pub time: Vec<f64>,
    /// Incident wave `eps_I`.
    pub incident: Vec<f64>,
    /// Reflected wave `eps_R` (negative while the specimen is loaded: tension).
    pub reflected: Vec<f64>,
    /// Transmitted wave `eps_T`.
    pub transmitted: Vec<f64>,
}

/// What the analysis needs to know of the bars and the specimen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KolskyBar {
    /// Young's modulus of the bars `E` (Pa).
    pub young_modulus: f64,
    /// Bar wave speed `c0 = sqrt(E / rho)` (m/s).
    pub wave_speed: f64,
    /// Bar over specimen initial cross-section, `A_b / A_s`.
    pub area_ratio: f64,
    /// Specimen initial length `l_s` (m).
    pub specimen_length: f64,
}

impl KolskyBar {
    /// The analysis window `(start, end)` at the specimen faces for a pulse that reaches the
    /// specimen at `arrival` and lasts `duration` plus a fall of `rise` (s).
    pub fn window(arrival: f64, duration: f64, rise: f64) -> (f64, f64) {
        (arrival - 2.0e-6, arrival + duration + rise + 5.0e-6)
    }

    /// Wave separation: the waves at the specimen faces from the gauges `(time, strain)` at
    /// `distances` `(d_i, d_t)` from the faces, by time shifts at `c0`, on the [`SAMPLING`]
    /// grid over `window`. `arrival` is when the incident pulse reaches the specimen.
    pub fn separate(
        &self,
        incident: &[(f64, f64)],
        transmitter: &[(f64, f64)],
        (d_i, d_t): (f64, f64),
        arrival: f64,
        (start, end): (f64, f64),
    ) -> BarWaves {
        let c0 = self.wave_speed;
        let count = ((end - start) / SAMPLING).ceil() as usize + 1;
        let mut waves = BarWaves::default();
        for k in 0..count {
            let t = start + k as f64 * SAMPLING;
            let before = t - d_i / c0;
            waves.time.push(t);
            waves.incident.push(if before < arrival + d_i / c0 {
                interpolate(incident, before)
            } else {
                0.0
            });
            waves.reflected.push(if t >= arrival {
                interpolate(incident, t + d_i / c0)
            } else {
                0.0
            });
            waves
                .transmitted
                .push(interpolate(transmitter, t + d_t / c0));
        }
        waves
    }

    /// Engineering stress, strain rate and strain by one analysis.
    pub fn analyse(&self, waves: &BarWaves, analysis: Analysis) -> StressStrain {
        let c0 = self.wave_speed;
        let modulus = self.young_modulus * self.area_ratio;
        let l_s = self.specimen_length;
        let mut out = StressStrain {
            time: waves.time.clone(),
            ..StressStrain::default()
        };
        for k in 0..waves.time.len() {
            let (i, r, t) = (waves.incident[k], waves.reflected[k], waves.transmitted[k]);
            let (stress, rate) = match analysis {
                Analysis::OneWave => (modulus * t, -2.0 * c0 * r / l_s),
                Analysis::TwoWave => (modulus * (i + r), -2.0 * c0 * r / l_s),
                Analysis::ThreeWave => (0.5 * modulus * (i + r + t), c0 * (i - r - t) / l_s),
            };
            out.stress.push(stress);
            out.strain_rate.push(rate);
        }
        let mut strain = 0.0;
        out.strain.push(0.0);
        for k in 1..out.time.len() {
            strain += 0.5
                * (out.strain_rate[k - 1] + out.strain_rate[k])
                * (out.time[k] - out.time[k - 1]);
            out.strain.push(strain);
        }
        out
    }
}

/// Fraction of the incident gauge's largest value that marks the pulse on a recorded signal.
pub const PULSE_THRESHOLD: f64 = 0.05;

/// The incident pulse on a recorded incident-gauge signal `(time, strain)`: `(start, end)`
/// at the gauge, where the signal first exceeds [`PULSE_THRESHOLD`] of its largest value and
/// where it falls back below it, each moved to the zero crossing of the straight line
/// through the threshold crossing and the 50 % crossing of that edge. `None` for a signal
/// without a pulse.
pub fn incident_pulse(signal: &[(f64, f64)]) -> Option<(f64, f64)> {
    let peak = signal.iter().map(|p| p.1).fold(0.0, f64::max);
    if peak <= 0.0 {
        return None;
    }
    let crossing = |level: f64, rising: bool, from: usize| -> Option<(usize, f64)> {
        (from.max(1)..signal.len()).find_map(|k| {
            let (t0, e0) = signal[k - 1];
            let (t1, e1) = signal[k];
            let crosses = if rising {
                e0 < level && e1 >= level
            } else {
                e0 >= level && e1 < level
            };
            crosses.then(|| (k, t0 + (level - e0) / (e1 - e0) * (t1 - t0)))
        })
    };
    let low = PULSE_THRESHOLD * peak;
    let (rise_index, rise_low) = crossing(low, true, 1)?;
    let (_, rise_half) = crossing(0.5 * peak, true, rise_index)?;
    let peak_index = signal.iter().position(|p| p.1 >= 0.5 * peak)?;
    let (fall_index, fall_half) = crossing(0.5 * peak, false, peak_index)?;
    let (_, fall_low) = crossing(low, false, fall_index).unwrap_or((signal.len(), fall_half));
    // Zero crossings of the edges through (t_low, 0.05) and (t_half, 0.5).
    let start = rise_low - (rise_half - rise_low) * PULSE_THRESHOLD / (0.5 - PULSE_THRESHOLD);
    let end = fall_low + (fall_low - fall_half) * PULSE_THRESHOLD / (0.5 - PULSE_THRESHOLD);
    (end > start).then_some((start, end))
}

/// The Kolsky analysis of a real bar's recorded gauges (compressive positive strains): the
/// pulse found on the incident gauge ([`incident_pulse`]), the waves separated at the
/// specimen faces, then `analysis`. Errors name what is missing.
pub fn analyse_recorded(
    bar: &KolskyBar,
    incident: &[(f64, f64)],
    transmitter: &[(f64, f64)],
    distances: (f64, f64),
    analysis: Analysis,
) -> Result<(BarWaves, StressStrain), String> {
    let (start, end) = incident_pulse(incident).ok_or(
        "no compressive incident pulse on the incident gauge (are the strains tension \
         positive? use --tension-positive)",
    )?;
    let arrival = start + distances.0 / bar.wave_speed;
    let span = end - start;
    let reflected_by = arrival + span + distances.0 / bar.wave_speed;
    let recorded_until = incident.last().map_or(f64::NEG_INFINITY, |p| p.0);
    if recorded_until < reflected_by {
        return Err(format!(
            "the incident gauge record ends at {recorded_until:e} s, before the reflected \
             pulse has passed the gauge ({reflected_by:e} s)"
        ));
    }
    if span > 2.0 * distances.0 / bar.wave_speed {
        return Err(format!(
            "the pulse ({span:e} s) is longer than the incident gauge's round trip to the \
             specimen ({:e} s): incident and reflected waves overlap at the gauge",
            2.0 * distances.0 / bar.wave_speed
        ));
    }
    let waves = bar.separate(
        incident,
        transmitter,
        distances,
        arrival,
        KolskyBar::window(arrival, span, 0.0),
    );
    let result = bar.analyse(&waves, analysis);
    Ok((waves, result))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_three_analyses_agree_on_waves_in_equilibrium() {
        // GOAL: the 1-, 2- and 3-wave formulas coincide when the specimen is in equilibrium.
        // SETUP: constant waves eps_I 2e-3, eps_R -0.5e-3, eps_T 1.5e-3 (eps_I + eps_R = eps_T)
        //        for 10 us on the default bars and specimen.
        // REFERENCE: stress E (A_b/A_s) eps_T, rate 2 c0 |eps_R| / l_s, strain = rate x time;
        //   to round-off (1e-12 relative).
        let spec = super::super::ShpbSpec::new(10.0);
        let bar = spec.kolsky_bar();
        let n = 101;
        let waves = BarWaves {
            time: (0..n).map(|k| k as f64 * SAMPLING).collect(),
            incident: vec![2.0e-3; n],
            reflected: vec![-0.5e-3; n],
            transmitted: vec![1.5e-3; n],
        };
        let stress = spec.bar_young_modulus * (12.7f64 / 6.0).powi(2) * 1.5e-3;
        let rate = 2.0 * spec.bar_wave_speed() * 0.5e-3 / spec.specimen_length;
        for analysis in [Analysis::OneWave, Analysis::TwoWave, Analysis::ThreeWave] {
            let out = bar.analyse(&waves, analysis);
            let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-12;
            assert!(out.stress.iter().all(|&s| close(s, stress)), "{analysis:?}");
            assert!(
                out.strain_rate.iter().all(|&r| close(r, rate)),
                "{analysis:?}"
            );
            assert!(close(out.max_strain(), rate * 10.0e-6), "{analysis:?}");
            assert!(close(out.mean_strain_rate(), rate), "{analysis:?}");
            assert_eq!(out.curve().len(), n);
        }
    }

    #[test]
    fn recorded_gauges_of_a_known_specimen_response_give_it_back() {
        // GOAL: the recorded-gauge path (pulse detection, wave separation, analyses) recovers
        //       a known specimen response from the gauge signals it would produce.
        // SETUP: 5000 m/s bars, A_b/A_s 4.48, l_s 4 mm, gauges 0.25 m from the faces; an
        //        incident pulse at the gauge from 40 us (5 us ramp, 60 us plateau of 1e-3,
        //        5 us ramp); a specimen in equilibrium transmitting 0.6 of the incident
        //        (eps_T = 0.6 eps_I, eps_R = -0.4 eps_I at the faces); gauges sampled every
        //        0.1 us, records long enough for the reflection.
        // REFERENCE: stress E (A_b/A_s) 0.6e-3 and strain rate 2 c0 0.4e-3 / l_s on the
        //        plateau (1e-9 relative); the pulse start found at 40 us (1e-9 s); the three
        //        analyses agree on the plateau.
        let bar = KolskyBar {
            young_modulus: 200.0e9,
            wave_speed: 5000.0,
            area_ratio: (12.7f64 / 6.0).powi(2),
            specimen_length: 4.0e-3,
        };
        let (d_i, d_t) = (0.25, 0.25);
        let pulse = |t: f64| -> f64 {
            let t = t - 40.0e-6;
            if t <= 0.0 || t >= 70.0e-6 {
                0.0
            } else if t < 5.0e-6 {
                1.0e-3 * t / 5.0e-6
            } else if t <= 65.0e-6 {
                1.0e-3
            } else {
                1.0e-3 * (70.0e-6 - t) / 5.0e-6
            }
        };
        // Incident wave at the face at time t: the gauge saw it d_i/c0 earlier.
        let face_incident = |t: f64| pulse(t - d_i / bar.wave_speed);
        let samples = 3000;
        let time = |k: usize| k as f64 * 0.1e-6;
        let incident: Vec<(f64, f64)> = (0..samples)
            .map(|k| {
                let t = time(k);
                // The incident pulse plus the reflected one coming back from the face.
                (t, pulse(t) - 0.4 * face_incident(t - d_i / bar.wave_speed))
            })
            .collect();
        let transmitted: Vec<(f64, f64)> = (0..samples)
            .map(|k| {
                let t = time(k);
                (t, 0.6 * face_incident(t - d_t / bar.wave_speed))
            })
            .collect();
        let (start, end) = incident_pulse(&incident).unwrap();
        assert!((start - 40.0e-6).abs() < 1e-9, "{start}");
        assert!((end - 110.0e-6).abs() < 1e-9, "{end}");
        let stress = bar.young_modulus * bar.area_ratio * 0.6e-3;
        let rate = 2.0 * bar.wave_speed * 0.4e-3 / bar.specimen_length;
        for analysis in [Analysis::OneWave, Analysis::TwoWave, Analysis::ThreeWave] {
            let (waves, out) =
                analyse_recorded(&bar, &incident, &transmitted, (d_i, d_t), analysis).unwrap();
            let arrival = 40.0e-6 + d_i / bar.wave_speed;
            let plateau: Vec<usize> = (0..waves.time.len())
                .filter(|&k| waves.time[k] > arrival + 10.0e-6 && waves.time[k] < arrival + 60.0e-6)
                .collect();
            assert!(plateau.len() > 400);
            for &k in &plateau {
                assert!((out.stress[k] / stress - 1.0).abs() < 1e-9, "{analysis:?}");
                assert!(
                    (out.strain_rate[k] / rate - 1.0).abs() < 1e-9,
                    "{analysis:?}"
                );
            }
            // The strain after the pulse: rate x (60 us plateau + two half ramps).
            assert!(
                (out.max_strain() / (rate * 65.0e-6) - 1.0).abs() < 1e-6,
                "{analysis:?}"
            );
        }
        // A record that ends before the reflection has passed the gauge is refused.
        let short = &incident[..1500];
        let error =
            analyse_recorded(&bar, short, &transmitted, (d_i, d_t), Analysis::OneWave).unwrap_err();
        assert!(error.contains("before the reflected pulse"), "{error}");
    }
}
