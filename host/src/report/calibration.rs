//! The calibration report (`report.md` with SVG figures) and the exported cards, after seed
//! 000's figures and tables:
//! - per-experiment recordings against the selected simulation (figs. 10, 13);
//! - the per-experiment error table per model (tables 1-3), fitted and held out;
//! - parallel coordinates of every instance's solution (fig. 11);
//! - stress-strain curves of the solutions at 1e-4 and 2000 /s (fig. 12);
//! - histograms of plastic strain, strain rate, temperature and triaxiality over the tracked
//!   material points of the selected simulation, which state the validity range (fig. 14);
//! - cards for LS-DYNA, Abaqus and OpenRadioss, and the stoss material TOML.

use super::cards;
use super::plots::{self, Series, Style};
use super::units::{display_units, DisplayUnits};
use crate::experiment::{Experiment, Outcome};
use crate::fit::campaign::LeaveOneOut;
use crate::fit::result::{recommend, ModelResult, SetScore};
use crate::fit::{Campaign, Evaluation, ModelSpace};
use crate::input::material::AnyMaterialFile;
use crate::measure::StateSample;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use stoss_kernel::drivers::{uniaxial_stress, UniaxialStressLoading};
use stoss_kernel::{Heating, Material, MaterialState};

/// Reads one quantity of a state sample.
type StateReader = fn(&StateSample) -> f64;

pub(crate) fn slug(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect()
}

pub(crate) fn experiment_name(campaign: &Campaign, index: usize) -> String {
    Path::new(&campaign.file.experiments[index].file)
        .file_stem()
        .map_or_else(
            || format!("experiment {index}"),
            |s| s.to_string_lossy().into_owned(),
        )
}

/// Isothermal uniaxial true stress-strain curve of `material` at `rate` (plastic strain 0-0.3).
fn flow_curve(material: &Material, rate: f64) -> Vec<(f64, f64)> {
    let mut material = *material;
    material.heating = Heating::Isothermal;
    let mut state = MaterialState::initial(298.0);
    let mut history = crate::history::History::default();
    let loading = UniaxialStressLoading {
        strain_rate: rate,
        final_strain: 0.32,
        steps: 320,
    };
    if uniaxial_stress(&material, &mut state, &loading, &mut history).is_err() {
        return Vec::new();
    }
    history
        .0
        .iter()
        .map(|r| (r.strain[0], r.stress[0] / 1e6))
        .collect()
}

fn errors_row(campaign: &Campaign, evaluation: &Evaluation) -> String {
    (0..campaign.experiments.len())
        .map(|i| {
            evaluation
                .scores
                .get(i)
                .copied()
                .flatten()
                .map_or_else(|| "-".to_string(), |s| format!("{:.4}", s.error))
        })
        .collect::<Vec<_>>()
        .join(" | ")
}

/// Write the report into `directory` (figures in `figures/`, cards in `cards/`). `outcomes[m]`
/// holds model `m`'s selected simulation of every campaign experiment, `starting[m]` its
/// starting constants' simulation of the held-out ones (`calibrate::run::Simulated`).
///
/// The cards are written as `card_options` says (unit system, material id, name).
pub fn write(
    directory: &Path,
    campaign: &Campaign,
    results: &[ModelResult],
    outcomes: &[Vec<Option<Outcome>>],
    starting: &[Vec<Option<Outcome>>],
    card_options: &cards::CardOptions,
) -> Result<(), String> {
    let figures = directory.join("figures");
    let cards = directory.join("cards");
    for dir in [&figures, &cards] {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let mut report = Report::new(campaign, figures, cards, card_options);
    report.header();
    report.recommendation(results, outcomes);
    report.model_selection(results);
    report.against_starting_constants(results);
    for (m, result) in results.iter().enumerate() {
        report.model(
            result,
            outcomes.get(m).map_or(&[], Vec::as_slice),
            starting.get(m).map_or(&[], Vec::as_slice),
        )?;
    }
    std::fs::write(
        directory.join("cards").join("README.md"),
        report.card_index(),
    )
    .map_err(|e| e.to_string())?;
    std::fs::write(directory.join("report.md"), report.md).map_err(|e| e.to_string())?;
    let json = serde_json::to_string_pretty(results).map_err(|e| e.to_string())?;
    // A result stoss's own reader refuses (a non-finite number written as null into a number
    // field) must never be written: `stoss diagnose` reads it back.
    serde_json::from_str::<Vec<ModelResult>>(&json).map_err(|e| {
        format!("result.json would not read back ({e}): a non-finite value in the results")
    })?;
    std::fs::write(directory.join("result.json"), json).map_err(|e| e.to_string())
}

/// The report being written: what its sections share, and `report.md` so far.
struct Report<'a> {
    campaign: &'a Campaign,
    /// Where the figures go (`figures/`).
    figures: PathBuf,
    /// Where the cards go (`cards/`).
    cards: PathBuf,
    /// The cards' unit system, material id and name.
    card_options: &'a cards::CardOptions,
    /// The fitted experiments.
    fitted: Vec<usize>,
    /// Every experiment's name, `(held out)` added to the held-out ones: the table columns.
    names: Vec<String>,
    /// The recommended constant set ([`recommend`]), once the recommendation is written.
    recommended: Option<SetScore>,
    /// Every set whose cards were written: its label, whether it is the recommended one, and
    /// its files (`cards/README.md`).
    card_sets: Vec<(String, bool, Vec<String>)>,
    md: String,
}

impl<'a> Report<'a> {
    fn new(
        campaign: &'a Campaign,
        figures: PathBuf,
        cards: PathBuf,
        card_options: &'a cards::CardOptions,
    ) -> Self {
        let names = (0..campaign.experiments.len())
            .map(|i| {
                let tag = if campaign.file.experiments[i].holdout {
                    " (held out)"
                } else {
                    ""
                };
                format!("{}{tag}", experiment_name(campaign, i))
            })
            .collect();
        Self {
            campaign,
            figures,
            cards,
            card_options,
            fitted: campaign.fitted(),
            names,
            recommended: None,
            card_sets: Vec::new(),
            md: String::new(),
        }
    }

    /// `cards/README.md`: which constant set each card holds, the recommended one first, so
    /// that the cards of different sets cannot be mixed up.
    fn card_index(&self) -> String {
        let mut text = format!(
            "# Cards of {}\n\nWritten by `stoss calibrate {}` in the {} unit system. Each \
             set's cards share a file stem; `report.md` (Recommendation) says why the \
             recommended set is recommended.\n",
            self.campaign.file.name,
            self.campaign.path.display(),
            self.card_options.units
        );
        let mut sets: Vec<&(String, bool, Vec<String>)> = self.card_sets.iter().collect();
        sets.sort_by_key(|(_, recommended, _)| !recommended);
        for (label, recommended, files) in sets {
            let _ = write!(
                text,
                "\n## {}{}\n\n{}\n",
                capitalised(label),
                if *recommended { " (recommended)" } else { "" },
                files
                    .iter()
                    .map(|f| {
                        let f = f.trim_start_matches("cards/");
                        match f.split_once(' ') {
                            Some((file, note)) => format!("- `{file}` {note}"),
                            None => format!("- `{f}`"),
                        }
                    })
                    .collect::<Vec<_>>()
                    .join("\n")
            );
        }
        text
    }

    /// Title, description, the campaign and optimiser settings, and how errors are measured.
    fn header(&mut self) {
        let (campaign, md) = (self.campaign, &mut self.md);
        let _ = writeln!(md, "# Calibration report: {}\n", campaign.file.name);
        if !campaign.file.description.is_empty() {
            let _ = writeln!(md, "{}\n", campaign.file.description);
        }
        let o = &campaign.file.optimiser;
        let _ = writeln!(md, "Campaign `{}`; base material `{}`. Optimiser: Latin hypercube start then GP expected improvement, budget {} simulations per instance, {} instance(s), seed {} (instance k uses seed + k), {} parallel simulations{}.\n",
            campaign.path.display(), campaign.base.name(), o.budget, o.instances, o.seed, o.parallel, match (o.leave_one_out, o.fold_budget) {
                (LeaveOneOut::Off, _) => String::new(),
                (every, fresh) => format!(
                    ", leave-one-out over the fitted experiments for {}{}",
                    if every == LeaveOneOut::Every { "every model" } else { "the selected model" },
                    fresh.map_or(String::new(), |n| format!(
                        " (each fold warm-started from the model's all-experiment simulations, {n} new simulation(s) per instance)"
                    ))
                ),
            });
        let _ = writeln!(md, "Error per experiment: RMSE of the residuals, each over its quantity's scale: the measured range of a resolved curve (seed 000), the quantity's magnitude (a relative error) for fewer than {} points or a range within {} standard deviations of the noise; total = weighted sum over the fitted experiments. `chi` = RMS of residuals over the recorded uncertainty, averaged over the fitted experiments (1 = at the noise).\n", crate::fit::objective::MIN_CURVE_POINTS, crate::fit::objective::RESOLVED_RANGE_Z);
        let scales: Vec<String> = campaign
            .experiments
            .iter()
            .enumerate()
            .map(|(i, e)| {
                format!(
                    "| {} | {} |",
                    experiment_name(campaign, i),
                    crate::fit::describe_scales(&crate::fit::error_scales(&e.recording))
                )
            })
            .collect();
        let _ = writeln!(
            md,
            "| experiment | error scale |\n|---|---|\n{}\n",
            scales.join("\n")
        );
    }

    /// Which constant set to use and why ([`recommend`]), at the top of the report, and the
    /// states it is valid for (those the experiments' tracked material points covered in the
    /// recommended model's simulations).
    fn recommendation(&mut self, results: &[ModelResult], outcomes: &[Vec<Option<Outcome>>]) {
        let sets: Vec<SetScore> = results
            .iter()
            .flat_map(|r| r.set_scores(self.campaign))
            .collect();
        let Some(r) = recommend(&sets) else {
            return;
        };
        let md = &mut self.md;
        let _ = writeln!(md, "## Recommendation\n\n**Use {}.**\n", r.set.label());
        for reason in &r.reasons {
            let _ = writeln!(md, "- {}.", capitalised(reason));
        }
        let model_outcomes = results
            .iter()
            .position(|m| m.model == r.set.model)
            .and_then(|m| outcomes.get(m))
            .map_or(&[][..], Vec::as_slice);
        let ranges = state_ranges(self.campaign, model_outcomes);
        if !ranges.is_empty() {
            let _ = writeln!(
                md,
                "- Valid for the states the experiments covered (tracked material points of \
                 the {} simulations; table \"Validity range\"): {}. Outside them the constants \
                 are extrapolated.",
                r.set.model,
                ranges
                    .iter()
                    .map(|(name, lo, hi)| {
                        format!("{name} {} to {}", to_digits(*lo, 3), to_digits(*hi, 3))
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        let posterior = results
            .iter()
            .find(|m| m.model == r.set.model)
            .and_then(|m| m.posterior.as_ref());
        if let Some(band) = posterior.and_then(|p| band_sentence(p.band_widths(self.campaign))) {
            let _ = writeln!(
                md,
                "- The 95 % prediction band of the calibrated {} constants (their posterior, \
                 sampled on the Gauss-Newton surrogate; section \"Posterior\") averages {band}.",
                r.set.model
            );
        }
        let stem = card_stem(&r.set.model, r.set.starting);
        let _ = writeln!(
            md,
            "- Its cards are `cards/{stem}.*` (the card titles say \"recommended\"); \
             `cards/README.md` lists every set's cards.\n"
        );
        self.recommended = Some(r.set);
    }

    /// The model selection table (every constant set: each model's calibrated constants and
    /// its starting ones, with their fitted values, reduced chi-square, information criterion
    /// and errors) and the selected model.
    fn model_selection(&mut self, results: &[ModelResult]) {
        let (campaign, names) = (self.campaign, &self.names);
        let md = &mut self.md;
        let _ = writeln!(
            md,
            "## Model selection\n\n`k`: values fitted to the recordings (0 for starting \
             constants, fixed before the data); `chi2/dof`: reduced chi-square over the fitted \
             recordings; `BIC`: chi-square + k ln N over them (Schwarz 1978), lower is better, \
             differences below 2 do not count.\n\n| constant set | k | fit error | chi2/dof \
             (fit) | BIC (fit) | held-out error | {} |\n|---|---|---|---|---|---|{}",
            names.join(" | "),
            "---|".repeat(names.len())
        );
        let number = |v: Option<f64>, digits: usize| {
            v.filter(|v| v.is_finite())
                .map_or("-".into(), |v| format!("{v:.digits$}"))
        };
        for r in results {
            let mut rows = vec![(false, &r.selected)];
            if let Some(baseline) = &r.baseline {
                rows.push((true, &baseline.evaluation));
            }
            for (starting, evaluation) in rows {
                let Some(set) = SetScore::of(&r.model, starting, evaluation, campaign, 0) else {
                    let _ = writeln!(
                        md,
                        "| {} | - | - (a simulation failed) | - | - | - | {} |",
                        if starting {
                            format!("{} (starting)", r.model)
                        } else {
                            r.model.clone()
                        },
                        errors_row(campaign, evaluation)
                    );
                    continue;
                };
                let _ = writeln!(
                    md,
                    "| {} | {} | {:.4} | {} | {} | {} | {} |",
                    set.short_label(),
                    set.fitted_values,
                    set.fit_error,
                    number(set.reduced_chi_square(), 2),
                    number(set.information_criterion(), 1),
                    number(set.holdout_error, 4),
                    errors_row(campaign, evaluation)
                );
            }
        }
        if let Some(selected) = crate::fit::result::selected_model_of(results, campaign) {
            let _ = writeln!(
                md,
                "\nSelected model: **{selected}**, the calibrated set the recommendation's rule \
                 picks among the calibrated sets alone (held-out prediction where experiments \
                 are held out, else the fit; a margin inside the noise decided by BIC); the one \
                 leave-one-out and the intervals run for with `\"selected\"`. Held-out \
                 experiments that choose the model are no longer a blind test of it: the \
                 leave-one-out folds are.\n"
            );
        }
    }

    /// Each model against its starting constants, the constants at a bound, and the
    /// uncertainty of the calibrated constants.
    fn against_starting_constants(&mut self, results: &[ModelResult]) {
        let (campaign, md) = (self.campaign, &mut self.md);
        let _ = writeln!(
            md,
            "### Against the starting constants\n\nThe starting constants of each model (its \
             `strength`, or the base material {}) are scored on the same experiments, as a \
             finalist is. The 95 % intervals of the calibrated constants are linearised \
             (Gauss-Newton) from the fitted recordings, scaled by the reduced chi-square; pairs \
             correlated beyond 0.95 are named.\n",
            campaign.base.name()
        );
        for r in results {
            if let Some(rejections) = r.rejection_summary() {
                let _ = writeln!(
                    md,
                    "- {rejections} (the lower flow-stress limit is {:.3e} Pa).",
                    campaign.flow_stress_floor()
                );
            }
            if let Some(fidelity) = r.fidelity_summary() {
                let _ = writeln!(md, "- {fidelity}.");
            }
            if let Some(verdict) = r.baseline_verdict() {
                let _ = writeln!(md, "- {verdict}.");
            }
            for bound in &r.at_bounds {
                let _ = writeln!(
                    md,
                    "- **{}: {bound}**: the optimum may lie beyond it (widen the bound if that is \
                     physical).",
                    r.model
                );
            }
            if let Some(model) = campaign.file.models.iter().find(|m| m.name == r.model) {
                for line in r.uncertainty_lines(&campaign.space(model).names) {
                    let _ = writeln!(md, "- {line}.");
                }
            }
        }
        let _ = writeln!(md);
    }

    /// One model's section; `outcomes` holds its selected simulation of every experiment,
    /// `starting` its starting constants' simulation of the held-out ones.
    fn model(
        &mut self,
        result: &ModelResult,
        outcomes: &[Option<Outcome>],
        starting: &[Option<Outcome>],
    ) -> Result<(), String> {
        let model = self.campaign.model(&result.model).ok_or("model missing")?;
        let space = self.campaign.space(model);
        self.constants(result, &space);
        self.instances(result);
        if result.finalists.len() > 1 {
            self.leave_one_out(result);
        }
        self.convergence(result)?;
        self.parallel_coordinates(result, &space)?;
        let (material_file, material) =
            space.material(&self.campaign.base, &result.selected.values)?;
        if let Some(metal) = material.j2() {
            // The starting constants' curves: the model's own starting point (its `strength`,
            // or the base material's).
            let starting = result
                .baseline
                .as_ref()
                .and_then(|b| {
                    space
                        .material(&self.campaign.base, &b.evaluation.values)
                        .ok()
                })
                .map(|(_, m)| m);
            self.flow_curves(result, metal, starting.as_ref().and_then(|m| m.j2()))?;
        }
        self.overlays(result, outcomes, starting)?;
        self.parity_and_residuals(result, outcomes)?;
        self.validity_range(result, outcomes)?;
        self.cards(result, material_file)?;
        // The recommended starting constants get their own cards, named apart.
        let starting_recommended = self
            .recommended
            .as_ref()
            .is_some_and(|set| set.starting && set.model == result.model);
        if let (true, Some(baseline)) = (starting_recommended, &result.baseline) {
            let (mut file, _) = space.material(&self.campaign.base, &baseline.evaluation.values)?;
            file.rename(
                format!(
                    "{} / {} starting constants (recommended by stoss)",
                    self.campaign.file.name, result.model
                ),
                format!(
                    "the starting constants of model {} in {}, recommended by stoss calibrate: \
                     they predict the held-out experiments best",
                    result.model,
                    self.campaign.path.display()
                ),
            );
            let stem = card_stem(&result.model, true);
            let written = write_cards(&self.cards, &stem, &file, self.card_options)?;
            self.card_sets.push((
                format!("the starting constants of {}", result.model),
                true,
                written.clone(),
            ));
            let _ = writeln!(
                self.md,
                "\n### Cards of the starting constants (recommended)\n\n{}\n",
                written
                    .iter()
                    .map(|w| format!("- `{w}`"))
                    .collect::<Vec<_>>()
                    .join("\n")
            );
        }
        Ok(())
    }

    /// The model's heading and its constants table: each constant's symbol and unit (stresses
    /// in MPa), its starting and selected values, the selected value's 95 % interval
    /// (linearised) and the search range.
    fn constants(&mut self, result: &ModelResult, space: &ModelSpace) {
        let md = &mut self.md;
        let _ = writeln!(
            md,
            "## Model `{}`\n\n### Constants\n\n| constant | symbol | unit | starting | \
             selected | 95 % interval | 95 % posterior | search range |\n|---|---|---|---|---|---|\
             ---|---|",
            result.model
        );
        let constants = space.constant_count();
        if constants == 0 {
            let _ = writeln!(
                md,
                "| (none: the material's constants are fixed; only set-up parameters are \
                 searched) | | | | | | | |"
            );
        }
        let units = space.units(&self.campaign.base);
        let symbols = space.symbols();
        let starting = result
            .baseline
            .as_ref()
            .map(|b| b.evaluation.values.clone())
            .or_else(|| space.starting_values(&self.campaign.base));
        let half_widths = result.uncertainty.as_ref().map(|u| &u.half_width_95);
        for (k, name) in space.names.iter().enumerate().take(constants) {
            let (unit, factor) = shown_unit(units[k]);
            let shown = |v: f64| significant(v * factor);
            let interval = match half_widths.map(|h| h.get(k).copied().flatten()) {
                Some(Some(half)) => format!("± {}", to_digits(half * factor, 2)),
                Some(None) => "undetermined".into(),
                None => "-".into(),
            };
            let credible = result.posterior.as_ref().map_or("-".into(), |p| {
                format!(
                    "{} to {}",
                    to_digits(p.lower_95[k] * factor, 3),
                    to_digits(p.upper_95[k] * factor, 3)
                )
            });
            let _ = writeln!(
                md,
                "| {name} | {} | {unit} | {} | {} | {interval} | {credible} | {} to {} |",
                symbols[k],
                starting
                    .as_ref()
                    .and_then(|s| s.get(k))
                    .map_or("-".into(), |v| shown(*v)),
                shown(result.selected.values[k]),
                shown(space.lower[k]),
                shown(space.upper[k]),
            );
        }
        if let Some(p) = &result.posterior {
            let worst = p.r_hat.iter().copied().fold(f64::NAN, f64::max);
            let pairs: Vec<String> = (0..p.correlation.len())
                .flat_map(|a| (a + 1..p.correlation.len()).map(move |b| (a, b)))
                .filter(|&(a, b)| p.correlation[a][b].abs() >= 0.5)
                .map(|(a, b)| {
                    format!(
                        "{}-{} {:+.2}",
                        symbols.get(a).map_or("?", String::as_str),
                        symbols.get(b).map_or("?", String::as_str),
                        p.correlation[a][b]
                    )
                })
                .collect();
            let _ = writeln!(
                md,
                "\n**Posterior** (section \"Posterior\" of docs/calibration.md): {} samples in {} \
                 chains of random-walk Metropolis on the Gauss-Newton surrogate of the misfit \
                 centred at the selected constants, the search box as the prior, the recorded \
                 uncertainties widened by s^2 = {:.2}; acceptance {:.0} %, largest R-hat {:.3}{}. \
                 The 95 % posterior interval is the 2.5-97.5 percentile range; unlike the \
                 linearised interval it respects the search bounds. Pairs correlated beyond 0.5 \
                 in the posterior: {}.{}",
                p.samples,
                p.chains,
                p.scale,
                100.0 * p.acceptance,
                worst,
                if worst > 1.1 {
                    " (above 1.1: the chains disagree, read the posterior with care)"
                } else {
                    ""
                },
                if pairs.is_empty() {
                    "none".into()
                } else {
                    pairs.join(", ")
                },
                {
                    let outside: Vec<String> = (0..p.least_squares.len())
                        .filter(|&k| !(p.lower_95[k]..=p.upper_95[k]).contains(&p.least_squares[k]))
                        .map(|k| {
                            let (unit, factor) = shown_unit(units[k]);
                            let unit = if unit == "-" { "" } else { unit };
                            format!(
                                "{} {}{}{unit}",
                                symbols.get(k).map_or("?", String::as_str),
                                to_digits(p.least_squares[k] * factor, 3),
                                if unit.is_empty() { "" } else { " " }
                            )
                        })
                        .collect();
                    if outside.is_empty() {
                        String::new()
                    } else {
                        format!(
                            " The chi-square's own least-squares point (on the linear \
                             surrogate) lies outside the posterior for {}: the calibration's \
                             objective (range- or magnitude-scaled errors per experiment) and the chi-square \
                             (each point by its recorded uncertainty) weigh the recordings \
                             differently.",
                            outside.join(", ")
                        )
                    }
                }
            );
        }
        if space.setup.is_empty() {
            return;
        }
        let _ = writeln!(
            md,
            "\n### Set-up parameters\n\nSearched beside the constants (nuisance parameters): \
             the constants above were found with these set-up values. Material files and cards \
             never carry them.\n\n| parameter | experiments | file value | lower | upper | \
             selected | unit |\n|---|---|---|---|---|---|---|"
        );
        for (k, parameter) in space.setup.iter().enumerate() {
            let at = constants + k;
            let _ = writeln!(
                md,
                "| {} | {} | {:.4e} | {:.4e} | {:.4e} | {:.6e} | {} |",
                &space.names[at][crate::fit::space::SETUP_PREFIX.len()..],
                parameter.experiments.join(", "),
                parameter.start,
                space.lower[at],
                space.upper[at],
                result.selected.values[at],
                units[at]
            );
        }
    }

    /// The instances table (fold, seed, fit error, simulations run and failed).
    fn instances(&mut self, result: &ModelResult) {
        let md = &mut self.md;
        let _ = writeln!(md, "\n### Instances\n\n| fold (left out) | instance | seed | fit error | simulated | failed |\n|---|---|---|---|---|---|");
        for i in &result.instances {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {:.4} | {} | {} |",
                i.fold.as_deref().unwrap_or("-"),
                i.instance,
                i.seed,
                i.fit_error,
                i.simulated,
                i.failed
            );
        }
    }

    /// The leave-one-out finalists table, and which folds kept the all-experiment fit.
    fn leave_one_out(&mut self, result: &ModelResult) {
        let (campaign, md, names) = (self.campaign, &mut self.md, &self.names);
        let _ = writeln!(md, "\n### Leave-one-out finalists (each fold's best, scored on all experiments)\n\n| left out | total (fitted) | {} |\n|---|---|{}", names.join(" | "), "---|".repeat(names.len()));
        let all_experiment = result.finalists.first().map(|(_, e)| &e.values);
        let mut unmoved = 0;
        for (fold, e) in &result.finalists {
            // A fold whose best is the all-experiment fit's constants (a warm-started fold
            // whose new simulations did not beat the shared history) predicts nothing new.
            let same = fold.is_some() && Some(&e.values) == all_experiment;
            unmoved += usize::from(same);
            let _ = writeln!(
                md,
                "| {}{} | {} | {} |",
                fold.as_deref().unwrap_or("none"),
                if same { " (= all-experiment fit)" } else { "" },
                e.total(campaign, &self.fitted)
                    .map_or("-".into(), |t| format!("{t:.4}")),
                errors_row(campaign, e)
            );
        }
        if unmoved > 0 {
            let _ = writeln!(
                md,
                "\n{unmoved} fold(s) kept the all-experiment fit's constants: without the \
                 left-out experiment the best constants known are still those, so their \
                 left-out error is not an independent prediction. A larger `fold_budget` \
                 (or independent folds) tests them harder."
            );
        }
    }

    /// The convergence figure: each instance's best error against simulations.
    fn convergence(&mut self, result: &ModelResult) -> Result<(), String> {
        let series: Vec<Series> = result
            .instances
            .iter()
            .enumerate()
            .map(|(k, i)| Series {
                errors: Vec::new(),
                label: format!("{} #{}", i.fold.as_deref().map_or("all", |f| f), i.instance),
                points: i
                    .history
                    .iter()
                    .enumerate()
                    .filter_map(|(n, v)| v.map(|v| ((n + 1) as f64, v)))
                    .collect(),
                style: Style::Line,
                colour: k,
            })
            .collect();
        let file = format!("{}-convergence.svg", slug(&result.model));
        plots::line_chart(
            &self.figures.join(&file),
            &format!("{}: best error vs simulations", result.model),
            "simulations",
            "best fit error",
            &series,
        )?;
        let _ = writeln!(self.md, "\n![convergence](figures/{file})\n");
        Ok(())
    }

    /// Parallel coordinates of every instance's solution, the selected one marked.
    fn parallel_coordinates(
        &mut self,
        result: &ModelResult,
        space: &ModelSpace,
    ) -> Result<(), String> {
        let lines: Vec<(Vec<f64>, bool)> = result
            .instances
            .iter()
            .map(|i| {
                let norm = i
                    .best
                    .values
                    .iter()
                    .enumerate()
                    .map(|(k, v)| (v - space.lower[k]) / (space.upper[k] - space.lower[k]))
                    .collect();
                (norm, i.best.values == result.selected.values)
            })
            .collect();
        let file = format!("{}-parallel.svg", slug(&result.model));
        plots::parallel_coordinates(
            &self.figures.join(&file),
            &format!(
                "{}: solutions of all instances (selected in red)",
                result.model
            ),
            &space.names,
            &lines,
        )?;
        let _ = writeln!(self.md, "![parallel coordinates](figures/{file})\n");
        Ok(())
    }

    /// Stress-strain curves of the selected J2 metal and of the starting constants (dashed)
    /// at 1e-4 and 2000 /s.
    fn flow_curves(
        &mut self,
        result: &ModelResult,
        metal: &Material,
        base: Option<&Material>,
    ) -> Result<(), String> {
        let mut series = Vec::new();
        for (k, rate) in [1e-4, 2000.0].into_iter().enumerate() {
            series.push(Series {
                errors: Vec::new(),
                label: format!("selected, {rate} /s"),
                points: flow_curve(metal, rate),
                style: Style::Line,
                colour: k,
            });
            if let Some(base) = base {
                series.push(Series {
                    errors: Vec::new(),
                    label: format!("starting constants, {rate} /s"),
                    points: flow_curve(base, rate),
                    style: Style::Dashed,
                    colour: k + 2,
                });
            }
        }
        let file = format!("{}-flow-curves.svg", slug(&result.model));
        plots::line_chart(
            &self.figures.join(&file),
            "isothermal flow curves at 298 K",
            "true strain",
            "true stress (MPa)",
            &series,
        )?;
        let _ = writeln!(self.md, "![flow curves](figures/{file})\n");
        Ok(())
    }

    /// Each experiment's recording (with its uncertainty as error bars) against the selected
    /// simulation, one figure each; a held-out experiment is marked as such and shows the
    /// starting constants' simulation too (dashed).
    fn overlays(
        &mut self,
        result: &ModelResult,
        outcomes: &[Option<Outcome>],
        starting: &[Option<Outcome>],
    ) -> Result<(), String> {
        let campaign = self.campaign;
        let _ = writeln!(
            self.md,
            "### Experiments: recording vs selected simulation\n\nRecorded points with their \
             uncertainty as error bars; on held-out experiments the starting constants' \
             simulation is dashed.\n"
        );
        for (i, experiment) in campaign.experiments.iter().enumerate() {
            let Some(Some(outcome)) = outcomes.get(i) else {
                continue;
            };
            let held_out = campaign.file.experiments[i].holdout;
            let start = starting
                .get(i)
                .and_then(Option::as_ref)
                .filter(|_| held_out);
            let band = result
                .posterior
                .as_ref()
                .and_then(|p| p.bands.get(i))
                .and_then(Option::as_ref);
            let (axes, series) = overlay_series(experiment, outcome, start, band);
            let title = if held_out {
                format!("{} (held out)", experiment.file.name)
            } else {
                experiment.file.name.clone()
            };
            let file = format!(
                "{}-{}.svg",
                slug(&result.model),
                slug(&experiment_name(campaign, i))
            );
            plots::line_chart(
                &self.figures.join(&file),
                &title,
                axes.position.0,
                axes.value.0,
                &series,
            )?;
            let _ = writeln!(self.md, "![{title}](figures/{file})");
        }
        Ok(())
    }

    /// Per experiment kind, a parity chart (simulated against recorded, the recorded
    /// uncertainty as error bars) and a residual chart (residual over the recorded
    /// uncertainty against position), one series per experiment, held-out ones named so.
    fn parity_and_residuals(
        &mut self,
        result: &ModelResult,
        outcomes: &[Option<Outcome>],
    ) -> Result<(), String> {
        let campaign = self.campaign;
        let mut kinds: Vec<&'static str> = Vec::new();
        for experiment in &campaign.experiments {
            let kind = crate::experiment::kind_name(&experiment.file.setup);
            if !kinds.contains(&kind) {
                kinds.push(kind);
            }
        }
        let mut written = Vec::new();
        for kind in kinds {
            let (mut parity, mut residuals) = (Vec::new(), Vec::new());
            let mut axes = None;
            for (i, experiment) in campaign.experiments.iter().enumerate() {
                if crate::experiment::kind_name(&experiment.file.setup) != kind {
                    continue;
                }
                let Some(Some(outcome)) = outcomes.get(i) else {
                    continue;
                };
                let label = if campaign.file.experiments[i].holdout {
                    format!("{} (held out)", experiment_name(campaign, i))
                } else {
                    experiment_name(campaign, i)
                };
                let (mut points, mut errors, mut whitened) = (Vec::new(), Vec::new(), Vec::new());
                for (point, predicted) in experiment.recording.iter().zip(&outcome.predicted) {
                    let units = display_units(&point.quantity);
                    axes.get_or_insert(units);
                    let scale = units.value.1;
                    points.push((point.value * scale, predicted * scale));
                    errors.push(point.uncertainty * scale);
                    whitened.push((
                        point.position * units.position.1,
                        (predicted - point.value) / point.uncertainty,
                    ));
                }
                let colour = parity.len();
                parity.push(Series {
                    label: label.clone(),
                    points,
                    style: Style::Markers,
                    colour,
                    errors,
                });
                residuals.push(Series {
                    label,
                    points: whitened,
                    style: Style::Markers,
                    colour,
                    errors: Vec::new(),
                });
            }
            let Some(axes) = axes else { continue };
            let stem = format!("{}-{}", slug(&result.model), slug(kind));
            plots::parity_chart(
                &self.figures.join(format!("{stem}-parity.svg")),
                &format!("{}: {kind}, simulated against recorded", result.model),
                axes.value.0,
                &parity,
            )?;
            plots::residual_chart(
                &self.figures.join(format!("{stem}-residuals.svg")),
                &format!(
                    "{}: {kind}, residuals over the recorded uncertainty",
                    result.model
                ),
                axes.position.0,
                &residuals,
                &[],
            )?;
            written.push((kind, stem));
        }
        if !written.is_empty() {
            let _ = writeln!(
                self.md,
                "\n### Parity and residuals per experiment kind\n\nSimulated against recorded \
                 (error bars: the recorded uncertainty; on the dashed line the simulation meets \
                 the recording) and the residuals in recorded uncertainties (within the dashed \
                 +-2 band at the noise).\n"
            );
            for (kind, stem) in written {
                let _ = writeln!(
                    self.md,
                    "![{kind} parity](figures/{stem}-parity.svg) \
                     ![{kind} residuals](figures/{stem}-residuals.svg)"
                );
            }
        }
        Ok(())
    }

    /// State histograms and their ranges per experiment type (seed 000 fig. 14): the final
    /// state of every tracked material point, and its peak plastic strain rate.
    fn validity_range(
        &mut self,
        result: &ModelResult,
        outcomes: &[Option<Outcome>],
    ) -> Result<(), String> {
        let kinds = outcomes_by_kind(self.campaign, outcomes);
        if kinds.is_empty() {
            return Ok(());
        }
        let md = &mut self.md;
        let _ = writeln!(md, "\n### Validity range (tracked material points, per experiment type)\n\n| quantity | experiment type | points | min | max |\n|---|---|---|---|---|");
        let quantities = STATE_QUANTITIES;
        for (k, (name, get)) in quantities.iter().enumerate() {
            let groups: Vec<(String, Vec<f64>)> = kinds
                .iter()
                .map(|(kind, list)| (kind.to_string(), state_values(list, k == 1, *get)))
                .collect();
            for (kind, values) in &groups {
                let (lo, hi) = values
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                        (a.min(*v), b.max(*v))
                    });
                let _ = writeln!(
                    md,
                    "| {name} | {kind} | {} | {lo:.4e} | {hi:.4e} |",
                    values.len()
                );
            }
            let file = format!("{}-hist-{}.svg", slug(&result.model), slug(name));
            plots::histogram(&self.figures.join(&file), name, name, &groups, 20)?;
        }
        let _ = writeln!(
            md,
            "\nThe constants are validated only within these ranges (seed 000 sec. 5).\n"
        );
        for (name, _) in quantities {
            let _ = writeln!(
                md,
                "![{name}](figures/{}-hist-{}.svg)",
                slug(&result.model),
                slug(name)
            );
        }
        Ok(())
    }

    /// The cards of the selected constants, named after the campaign and model, and their
    /// list.
    fn cards(
        &mut self,
        result: &ModelResult,
        mut material_file: AnyMaterialFile,
    ) -> Result<(), String> {
        let campaign = self.campaign;
        let recommended = self
            .recommended
            .as_ref()
            .is_some_and(|set| !set.starting && set.model == result.model);
        let band = result
            .posterior
            .as_ref()
            .and_then(|p| band_sentence(p.band_widths(campaign)))
            .map_or(String::new(), |b| format!("; 95 % prediction band {b}"));
        material_file.rename(
            format!(
                "{} / {} (stoss calibration{}{band})",
                campaign.file.name,
                result.model,
                if recommended {
                    ", recommended"
                } else {
                    ", not the recommended set"
                }
            ),
            format!(
                "stoss calibrate {}, model {}, starting from {}{}",
                campaign.path.display(),
                result.model,
                campaign.base.name(),
                if recommended {
                    ": the constant set the report recommends"
                } else {
                    ": the report recommends another set (report.md, Recommendation)"
                }
            ),
        );
        let written = write_cards(
            &self.cards,
            &card_stem(&result.model, false),
            &material_file,
            self.card_options,
        )?;
        self.card_sets.push((
            format!("the calibrated {} constants{band}", result.model),
            recommended,
            written.clone(),
        ));
        let _ = writeln!(self.md, "\n### Cards\n\n{}\n(`.toml`: `stoss simulate --material`; `.k`: LS-DYNA's own card where the family has one; `-mat224.k`: LS-DYNA `*MAT_TABULATED_JOHNSON_COOK` tables of this model's flow stress, for any family; `-plastic.inp`: the same tables as Abaqus/Explicit `*PLASTIC, RATE=` data; `.inp`: Abaqus; `.rad`: OpenRadioss; `-umat.k`, `-umat.inp`: the stoss user material's card for LS-DYNA and Abaqus, for any model (docs/user-material.md).)\n", written.iter().map(|w| format!("- `{w}`")).collect::<Vec<_>>().join("\n"));
        Ok(())
    }
}

/// The recorded and simulated series of one experiment's overlay, by quantity, and the units
/// of its axes: stresses in MPa, lengths in mm, times in us; the axes name the first
/// quantity's units, the legend every other's.
fn overlay_series(
    experiment: &Experiment,
    outcome: &Outcome,
    starting: Option<&Outcome>,
    band: Option<&crate::fit::posterior::PredictionBand>,
) -> (DisplayUnits, Vec<Series>) {
    let mut groups: Vec<String> = experiment
        .recording
        .iter()
        .map(|p| p.quantity.clone())
        .collect();
    groups.dedup();
    let mut series = Vec::new();
    let axes = display_units(groups.first().map_or("", String::as_str));
    for (g, quantity) in groups.iter().enumerate() {
        let units = display_units(quantity);
        let (x_scale, y_scale) = (units.position.1, units.value.1);
        let recorded: Vec<(f64, f64)> = experiment
            .recording
            .iter()
            .filter(|p| &p.quantity == quantity)
            .map(|p| (p.position * x_scale, p.value * y_scale))
            .collect();
        let uncertainty: Vec<f64> = experiment
            .recording
            .iter()
            .filter(|p| &p.quantity == quantity)
            .map(|p| p.uncertainty * y_scale)
            .collect();
        // Values at this quantity's recorded points (a simulation's predictions, a band's
        // edge), in display units, by position.
        let at_points = |values: &[f64]| {
            let mut points: Vec<(f64, f64)> = experiment
                .recording
                .iter()
                .zip(values)
                .filter(|(p, _)| &p.quantity == quantity)
                .map(|(p, v)| (p.position * x_scale, *v * y_scale))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            points
        };
        let predicted = at_points(&outcome.predicted);
        let quantity = if units == axes {
            quantity.clone()
        } else {
            format!("{quantity} [{}; {}]", units.value.0, units.position.0)
        };
        // A quantity measured at one position (a Taylor rod's final length or footprint, a
        // peak deflection) has no line to draw: its simulated value is a marker beside the
        // recorded one.
        let single = predicted.windows(2).all(|w| w[0].0 == w[1].0);
        series.push(Series {
            errors: uncertainty,
            label: format!("{quantity} recorded"),
            points: recorded,
            style: Style::Markers,
            colour: 3 * g,
        });
        series.push(Series {
            errors: Vec::new(),
            label: format!("{quantity} simulated"),
            points: predicted,
            style: if single { Style::Markers } else { Style::Line },
            colour: 3 * g + 1,
        });
        if let Some(band) = band {
            // The 95 % prediction band's edges at this quantity's points.
            for (edge_name, values) in [("lower", &band.lower), ("upper", &band.upper)] {
                series.push(Series {
                    errors: Vec::new(),
                    label: format!("{quantity} 95 % band, {edge_name}"),
                    points: at_points(values),
                    style: if single {
                        Style::Markers
                    } else {
                        Style::Dashed
                    },
                    colour: 3 * g + 1,
                });
            }
        }
        if let Some(starting) = starting {
            series.push(Series {
                errors: Vec::new(),
                label: format!("{quantity} simulated, starting constants"),
                points: at_points(&starting.predicted),
                style: if single {
                    Style::Markers
                } else {
                    Style::Dashed
                },
                colour: 3 * g + 2,
            });
        }
    }
    (axes, series)
}

/// The unit a constant is shown in, and the factor from its SI unit: stresses in MPa, every
/// other constant in its SI unit.
fn shown_unit(si: &str) -> (&str, f64) {
    match si {
        "Pa" => ("MPa", 1e-6),
        other => (other, 1.0),
    }
}

/// `value` to five significant digits (a constant), plainly where that is readable (1e-3 to
/// 1e5) and in exponent notation otherwise.
fn significant(value: f64) -> String {
    to_digits(value, 5)
}

/// `value` to `digits` significant digits, plainly from 1e-3 to 1e5, else in exponent notation.
fn to_digits(value: f64, digits: usize) -> String {
    let magnitude = value.abs();
    if value == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&magnitude) {
        let decimals =
            (digits as i32 - 1 - libm::floor(libm::log10(magnitude)) as i32).max(0) as usize;
        format!("{value:.decimals$}")
    } else {
        format!("{value:.prec$e}", prec = digits.saturating_sub(1))
    }
}

/// "+-a % on the fitted experiments and +-b % on the held-out ones" from
/// [`crate::fit::posterior::Posterior::band_widths`].
fn band_sentence(widths: (Option<f64>, Option<f64>)) -> Option<String> {
    match widths {
        (Some(fit), Some(held)) => Some(format!(
            "±{:.1} % of the recorded values on the fitted experiments and ±{:.1} % on the \
             held-out ones",
            100.0 * fit,
            100.0 * held
        )),
        (Some(fit), None) => Some(format!(
            "±{:.1} % of the recorded values on the fitted experiments",
            100.0 * fit
        )),
        (None, Some(held)) => Some(format!(
            "±{:.1} % of the recorded values on the held-out experiments",
            100.0 * held
        )),
        (None, None) => None,
    }
}

/// `text` with its first letter upper-case (a reason written as a sentence).
fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    chars.next().map_or(String::new(), |first| {
        first.to_uppercase().collect::<String>() + chars.as_str()
    })
}

/// The file stem of a constant set's cards: `<model>` for the calibrated constants,
/// `<model>-starting` for the starting ones.
fn card_stem(model: &str, starting: bool) -> String {
    if starting {
        format!("{}-starting", slug(model))
    } else {
        slug(model)
    }
}

/// The state quantities of the validity range (seed 000 fig. 14), each read from a tracked
/// point's final sample (or, for the rate, its peak).
const STATE_QUANTITIES: [(&str, StateReader); 4] = [
    ("plastic strain", |s| s.plastic_strain),
    ("peak plastic strain rate (1/s)", |s| s.plastic_strain_rate),
    ("temperature (K)", |s| s.temperature),
    ("triaxiality", |s| s.triaxiality),
];

/// The range of every state quantity over the tracked points of all `outcomes`:
/// `(quantity, min, max)`; empty if no experiment tracked points.
fn state_ranges(
    campaign: &Campaign,
    outcomes: &[Option<Outcome>],
) -> Vec<(&'static str, f64, f64)> {
    let kinds = outcomes_by_kind(campaign, outcomes);
    let all: Vec<&Outcome> = kinds
        .iter()
        .flat_map(|(_, list)| list.iter().copied())
        .collect();
    if all.is_empty() {
        return Vec::new();
    }
    STATE_QUANTITIES
        .iter()
        .enumerate()
        .filter_map(|(k, (name, get))| {
            let values = state_values(&all, k == 1, *get);
            let (lo, hi) = values
                .iter()
                .filter(|v| v.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(*v), b.max(*v))
                });
            (lo <= hi).then_some((*name, lo, hi))
        })
        .collect()
}

/// The outcomes that tracked material points, grouped by experiment type in campaign order.
fn outcomes_by_kind<'o>(
    campaign: &Campaign,
    outcomes: &'o [Option<Outcome>],
) -> Vec<(&'static str, Vec<&'o Outcome>)> {
    let mut kinds: Vec<(&str, Vec<&Outcome>)> = Vec::new();
    for (experiment, outcome) in campaign.experiments.iter().zip(outcomes) {
        let Some(outcome) = outcome else { continue };
        if outcome.states.is_empty() {
            continue;
        }
        let kind = crate::experiment::kind_name(&experiment.file.setup);
        match kinds.iter_mut().find(|(k, _)| *k == kind) {
            Some((_, list)) => list.push(outcome),
            None => kinds.push((kind, vec![outcome])),
        }
    }
    kinds
}

/// One quantity over the tracked points of `outcomes`: each point's final value, or its peak
/// plastic strain rate if `peak_rate`.
fn state_values(outcomes: &[&Outcome], peak_rate: bool, get: StateReader) -> Vec<f64> {
    outcomes
        .iter()
        .flat_map(|o| o.states.iter())
        .filter_map(|h| {
            if peak_rate {
                Some(
                    h.samples
                        .iter()
                        .map(|s| s.plastic_strain_rate)
                        .fold(0.0, f64::max),
                )
            } else {
                h.samples.last().map(get)
            }
        })
        .collect()
}

/// Write the cards of `material_file` into `card_dir` as `<stem>.<ext>`: the stoss TOML, the
/// metal cards, the user-material cards and the tabulated cards. Returns the list for the
/// report (a reason where a card could not be written).
fn write_cards(
    card_dir: &Path,
    stem: &str,
    material_file: &AnyMaterialFile,
    options: &cards::CardOptions,
) -> Result<Vec<String>, String> {
    let mut written = vec![format!("cards/{stem}.toml")];
    std::fs::write(
        card_dir.join(format!("{stem}.toml")),
        material_file.to_toml(),
    )
    .map_err(|e| e.to_string())?;
    let metal_file = match material_file {
        AnyMaterialFile::J2(file) => Some(file),
        AnyMaterialFile::Rht(_) | AnyMaterialFile::Kc(_) => None,
    };
    for (ext, card) in [
        ("k", metal_file.and_then(|f| cards::ls_dyna(f, options))),
        ("inp", metal_file.and_then(|f| cards::abaqus(f, options))),
        (
            "rad",
            metal_file.and_then(|f| cards::open_radioss(f, options)),
        ),
    ] {
        if let Some(card) = card {
            std::fs::write(card_dir.join(format!("{stem}.{ext}")), card)
                .map_err(|e| e.to_string())?;
            written.push(format!("cards/{stem}.{ext}"));
        }
    }
    // The user material's initial temperature: a metal model's reference temperature where it
    // has one (JC-type thermal terms), else 293 K; edit P6 for another.
    let initial_temperature = metal_file
        .and_then(|file| file.strength.constant_named("reference_temperature"))
        .unwrap_or(293.0);
    match cards::user_material::cards(material_file, initial_temperature) {
        Ok((dyna, abaqus)) => {
            for (suffix, text) in [("umat.k", dyna), ("umat.inp", abaqus)] {
                std::fs::write(card_dir.join(format!("{stem}-{suffix}")), text)
                    .map_err(|e| e.to_string())?;
                written.push(format!("cards/{stem}-{suffix}"));
            }
        }
        Err(reason) => written.push(format!("(no user-material card: {reason})")),
    }
    if !options.units.is_si() {
        written.push(format!(
            "(the user-material cards stay in SI, kg-m-s-Pa: the stoss C ABI computes in SI;              the other cards are in {})",
            options.units
        ));
    }
    for (suffix, card) in [
        (
            "mat224.k",
            metal_file.and_then(|f| cards::tabulated::ls_dyna(f, options)),
        ),
        (
            "plastic.inp",
            metal_file.and_then(|f| cards::tabulated::abaqus(f, options)),
        ),
    ] {
        if let Some((card, _, error)) = card {
            std::fs::write(card_dir.join(format!("{stem}-{suffix}")), card)
                .map_err(|e| e.to_string())?;
            written.push(format!(
                "cards/{stem}-{suffix} (largest interpolation error {:.2} %)",
                100.0 * error.relative
            ));
        }
    }
    Ok(written)
}
