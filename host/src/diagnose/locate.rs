//! Locate the misfit: per experiment, the whitened residuals `z = (predicted - recorded) /
//! uncertainty` against the recorded uncertainty; a chi-square test of the whole recording,
//! the runs test and lag-1 autocorrelation (structure against noise), and chi-square tests over
//! windows of consecutive points, Bonferroni-corrected over every window of the campaign.
//! Significant windows merge into bands; each band is related to the state the material went
//! through there (tracked plastic strain, strain rate, temperature, triaxiality, pressure).

use super::stats::{chi_square_upper_tail, lag1_autocorrelation, runs_test, RunsTest};
use crate::experiment::uniaxial::RecordedStrain;
use crate::experiment::{Experiment, Outcome, Setup};
use crate::measure::StateSample;
use serde::{Deserialize, Serialize};

/// A run of consecutive measurement points whose misfit is significant.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Band {
    /// Recorded quantity.
    pub quantity: String,
    /// First and last position of the band (the recording's position unit).
    pub start: f64,
    /// Last position.
    pub end: f64,
    /// Points in the band.
    pub points: usize,
    /// Chi-square of the band's whitened residuals.
    pub chi_square: f64,
    /// Its p-value (chi-square with `points` degrees of freedom).
    pub p_value: f64,
    /// Mean relative misfit `(predicted - recorded) / |recorded|` over the band.
    pub mean_relative: f64,
    /// What the material went through there (if states are tracked).
    pub conditions: Option<Conditions>,
    /// Indices of its points in the recording.
    #[serde(default)]
    pub members: Vec<usize>,
}

/// Ranges of the tracked state over a region and the whole history.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Conditions {
    /// Where (e.g. `outer surface, 0-4 mm from the impact face`).
    pub region: String,
    /// Tracked points over the region.
    pub points: usize,
    /// Largest plastic strain reached.
    pub max_plastic_strain: f64,
    /// Largest plastic strain rate reached (1/s).
    pub max_strain_rate: f64,
    /// Largest temperature reached (K).
    pub max_temperature: f64,
    /// Temperature at the start (K).
    pub initial_temperature: f64,
    /// Range of the stress triaxiality while yielding.
    pub triaxiality: (f64, f64),
    /// Largest pressure (Pa).
    pub max_pressure: f64,
}

/// One whitened residual.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Residual {
    /// Quantity.
    pub quantity: String,
    /// Position.
    pub position: f64,
    /// `(predicted - recorded) / uncertainty`.
    pub whitened: f64,
    /// `(predicted - recorded) / |recorded|`.
    pub relative: f64,
}

/// The misfit of one experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExperimentMisfit {
    /// Index in the campaign.
    pub index: usize,
    /// Display name.
    pub name: String,
    /// Held out of the fit.
    pub holdout: bool,
    /// Residuals in recording order.
    pub residuals: Vec<Residual>,
    /// Chi-square over the recording.
    pub chi_square: f64,
    /// Its p-value (`n` degrees of freedom).
    pub p_value: f64,
    /// Runs test of the longest quantity series (when it has 6 points or more).
    pub runs: Option<RunsTest>,
    /// Lag-1 autocorrelation of that series.
    pub autocorrelation: f64,
    /// Significant bands.
    pub bands: Vec<Band>,
    /// The misfit is significant and structured (not noise).
    pub structured: bool,
}

/// Window length for a series of `n` points.
fn window_length(n: usize) -> usize {
    n.div_ceil(5).clamp(3, 8).min(n.max(1))
}

/// Index ranges of the quantity series of a recording (consecutive points of one quantity).
fn series(experiment: &Experiment) -> Vec<(String, Vec<usize>)> {
    let mut out: Vec<(String, Vec<usize>)> = Vec::new();
    for (i, point) in experiment.recording.iter().enumerate() {
        match out.last_mut() {
            Some((quantity, indices)) if *quantity == point.quantity => indices.push(i),
            _ => out.push((point.quantity.clone(), vec![i])),
        }
    }
    out
}

/// Number of windows the campaign's recordings split into (the Bonferroni count).
pub fn window_count(experiments: &[&Experiment]) -> usize {
    experiments
        .iter()
        .flat_map(|e| series(e))
        .map(|(_, indices)| indices.len().div_ceil(window_length(indices.len())))
        .sum()
}

/// Locate the misfit of `experiment` given its predictions. `alpha_window` is the
/// (already corrected) significance of a window, `alpha_experiment` that of the whole
/// recording.
pub fn locate(
    index: usize,
    experiment: &Experiment,
    holdout: bool,
    predicted: &[f64],
    outcome: Option<&Outcome>,
    alpha_window: f64,
    alpha_experiment: f64,
) -> ExperimentMisfit {
    let residuals: Vec<Residual> = experiment
        .recording
        .iter()
        .zip(predicted)
        .map(|(point, p)| Residual {
            quantity: point.quantity.clone(),
            position: point.position,
            whitened: (p - point.value) / point.uncertainty,
            relative: (p - point.value) / point.value.abs().max(f64::MIN_POSITIVE),
        })
        .collect();
    let chi_square: f64 = residuals.iter().map(|r| r.whitened * r.whitened).sum();
    let p_value = chi_square_upper_tail(chi_square, residuals.len() as f64);
    let all_series = series(experiment);
    let longest = all_series.iter().max_by_key(|(_, indices)| indices.len());
    let (runs, autocorrelation) = match longest {
        Some((_, indices)) if indices.len() >= 6 => {
            let z: Vec<f64> = indices.iter().map(|&i| residuals[i].whitened).collect();
            (Some(runs_test(&z)), lag1_autocorrelation(&z))
        }
        _ => (None, 0.0),
    };
    let mut bands: Vec<Band> = Vec::new();
    for (quantity, indices) in &all_series {
        let length = window_length(indices.len());
        let mut open: Option<Vec<usize>> = None;
        let close = |members: Vec<usize>, bands: &mut Vec<Band>| {
            let chi: f64 = members
                .iter()
                .map(|&i| residuals[i].whitened * residuals[i].whitened)
                .sum();
            let start = residuals[members[0]].position;
            let end = residuals[*members.last().unwrap_or(&members[0])].position;
            bands.push(Band {
                quantity: quantity.clone(),
                start,
                end,
                points: members.len(),
                chi_square: chi,
                p_value: chi_square_upper_tail(chi, members.len() as f64),
                mean_relative: members.iter().map(|&i| residuals[i].relative).sum::<f64>()
                    / members.len() as f64,
                conditions: outcome.and_then(|o| conditions(experiment, o, quantity, start, end)),
                members,
            });
        };
        for window in indices.chunks(length) {
            let chi: f64 = window
                .iter()
                .map(|&i| residuals[i].whitened * residuals[i].whitened)
                .sum();
            if chi_square_upper_tail(chi, window.len() as f64) < alpha_window {
                open.get_or_insert_with(Vec::new).extend_from_slice(window);
            } else if let Some(members) = open.take() {
                close(members, &mut bands);
            }
        }
        if let Some(members) = open.take() {
            close(members, &mut bands);
        }
    }
    let structure = !bands.is_empty() || runs.is_some_and(|r| r.p_value < alpha_experiment);
    ExperimentMisfit {
        index,
        name: experiment.file.name.clone(),
        holdout,
        residuals,
        chi_square,
        p_value,
        runs,
        autocorrelation,
        structured: p_value < alpha_experiment && structure,
        bands,
    }
}

/// The state ranges over the region of the specimen that drives points `start..=end` of
/// `quantity`.
pub(super) fn conditions(
    experiment: &Experiment,
    outcome: &Outcome,
    quantity: &str,
    start: f64,
    end: f64,
) -> Option<Conditions> {
    let (region, samples): (String, Vec<&StateSample>) = match &experiment.file.setup {
        Setup::Uniaxial(spec) => {
            let history = outcome.states.first()?;
            // The band is in the recording's strain measure: the total strain of the
            // constant-rate driver is its rate times the time.
            let strain = |s: &StateSample| match spec.recorded_strain {
                RecordedStrain::Plastic => s.plastic_strain,
                RecordedStrain::Total => spec.strain_rate * s.time,
            };
            let samples: Vec<&StateSample> = history
                .samples
                .iter()
                .filter(|s| strain(s) >= start && strain(s) <= end)
                .collect();
            (
                format!(
                    "the homogeneous specimen at {} {start:.3}-{end:.3}",
                    spec.recorded_strain.name()
                ),
                samples,
            )
        }
        Setup::Taylor(spec) => {
            let field = outcome.field.as_ref()?;
            let low = field
                .positions
                .iter()
                .map(|p| p[1])
                .fold(f64::INFINITY, f64::min);
            let element_size = 0.5 * spec.diameter / spec.radial_elements as f64;
            let (from, to, region) = match quantity {
                "diameter" => (
                    start - 0.5 * element_size,
                    end + 0.5 * element_size,
                    format!(
                        "the outer surface {:.1}-{:.1} mm from the impact face",
                        start * 1e3,
                        end * 1e3
                    ),
                ),
                "footprint_diameter" => (
                    0.0,
                    2.0 * element_size,
                    "the impact face (footprint)".to_string(),
                ),
                _ => (0.0, f64::INFINITY, "the whole rod".to_string()),
            };
            let mut samples = Vec::new();
            for history in &outcome.states {
                let Some(element) = history
                    .label
                    .strip_prefix("element ")
                    .and_then(|e| e.parse::<usize>().ok())
                else {
                    continue;
                };
                let nodes = field.mesh.elements.get(element)?;
                let z = nodes.iter().map(|&n| field.positions[n][1]).sum::<f64>() / 4.0 - low;
                if z >= from && z <= to {
                    samples.extend(history.samples.iter());
                }
            }
            (region, samples)
        }
        Setup::Penetration(_) => {
            // The two tracked target columns (axis; rod radius) over the recorded times.
            let (from, to) = match quantity {
                "nose_depth" | "rod_length" => (start, end),
                _ => (f64::NEG_INFINITY, f64::INFINITY),
            };
            let samples: Vec<&StateSample> = outcome
                .states
                .iter()
                .filter(|h| h.label.starts_with("target "))
                .flat_map(|h| h.samples.iter())
                .filter(|s| s.time >= from && s.time <= to)
                .collect();
            let region = if from.is_finite() {
                format!(
                    "the target columns ahead of the rod (axis and rod radius) at {:.1}-{:.1} us",
                    from * 1e6,
                    to * 1e6
                )
            } else {
                "the target columns ahead of the rod (axis and rod radius)".to_string()
            };
            (region, samples)
        }
        _ => (
            "the tracked elements".to_string(),
            outcome
                .states
                .iter()
                .flat_map(|h| h.samples.iter())
                .collect(),
        ),
    };
    if samples.is_empty() {
        return None;
    }
    let max = |f: fn(&StateSample) -> f64| {
        samples
            .iter()
            .map(|s| f(s))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let yielding: Vec<f64> = samples
        .iter()
        .filter(|s| s.plastic_strain_rate > 0.0)
        .map(|s| s.triaxiality)
        .collect();
    let triaxiality = if yielding.is_empty() {
        (0.0, 0.0)
    } else {
        (
            yielding.iter().copied().fold(f64::INFINITY, f64::min),
            yielding.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    };
    Some(Conditions {
        region,
        points: samples.len(),
        max_plastic_strain: max(|s| s.plastic_strain),
        max_strain_rate: max(|s| s.plastic_strain_rate),
        max_temperature: max(|s| s.temperature),
        initial_temperature: samples
            .iter()
            .map(|s| s.temperature)
            .fold(f64::INFINITY, f64::min),
        triaxiality,
        max_pressure: max(|s| s.pressure),
    })
}
