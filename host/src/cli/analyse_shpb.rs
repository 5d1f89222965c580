//! `stoss analyse-shpb <gauges.csv> --bar-modulus "200 GPa" ...`: the Kolsky analysis of a
//! real split Hopkinson bar's recorded strain-gauge signals, the same analysis the simulated
//! bar uses (`experiment::shpb::kolsky`). It writes the specimen's engineering stress, strain
//! and strain rate against time by the 1-, 2- and 3-wave analyses, and the chosen analysis's
//! loading branch as a stoss recording (`engineering_stress` at engineering strain) that a
//! `shpb` experiment of a campaign can fit.
//!
//! The gauges file is CSV with the header `time,incident,transmitted`; each column may carry a
//! unit (`time [us]`, `incident [microstrain]`); lines starting with `#` are comments.
//! Strains are compressive positive unless `--tension-positive` says the bridges read
//! tension positive.

use super::output::say;
use crate::experiment::shpb::kolsky::{analyse_recorded, incident_pulse, KolskyBar};
use crate::experiment::shpb::{Analysis, StressStrain};
use crate::input::recording::header_cell;
use crate::input::units::{self, Dimension};
use clap::Args;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `stoss analyse-shpb`. Quantities take units (`"200 GPa"`, `"12.7 mm"`); a
/// bare number is SI.
#[derive(Debug, Args)]
pub struct AnalyseShpbArgs {
    /// Gauge signals: CSV `time,incident,transmitted` (units in brackets allowed).
    pub gauges: PathBuf,
    /// Young's modulus of the bars.
    #[arg(long)]
    pub bar_modulus: String,
    /// Density of the bars.
    #[arg(long)]
    pub bar_density: String,
    /// Bar diameter.
    #[arg(long)]
    pub bar_diameter: String,
    /// Specimen initial diameter.
    #[arg(long)]
    pub specimen_diameter: String,
    /// Specimen initial length.
    #[arg(long)]
    pub specimen_length: String,
    /// Distance of the incident-bar gauge from the specimen face.
    #[arg(long)]
    pub incident_gauge: String,
    /// Distance of the transmitter-bar gauge from the specimen face.
    #[arg(long)]
    pub transmitter_gauge: String,
    /// The analysis written to the recording: 1-wave (transmitted), 2-wave (front face) or
    /// 3-wave (mean).
    #[arg(long, default_value = "1-wave")]
    pub analysis: String,
    /// The bridges read tension positive (the signals are negated).
    #[arg(long)]
    pub tension_positive: bool,
    /// Relative uncertainty written with each recorded point (the recording format needs
    /// one; state your bar's).
    #[arg(long, default_value_t = 0.02)]
    pub uncertainty: f64,
    /// Output stem: `<output>.csv` (time series of the three analyses) and
    /// `<output>.recording.csv` (the chosen analysis's loading branch).
    #[arg(long)]
    pub output: PathBuf,
}

/// Run `stoss analyse-shpb`.
pub fn run(args: &AnalyseShpbArgs) -> ExitCode {
    match analyse(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// A positive quantity given on the command line, in SI.
fn quantity(flag: &str, text: &str, dimension: Dimension) -> Result<f64, String> {
    let value = match text.trim().parse::<f64>() {
        Ok(bare) => Ok(Some(bare)),
        Err(_) => units::quantity_to_si(text, dimension),
    };
    let value = match value {
        Ok(Some(value)) => value,
        Ok(None) => text
            .trim()
            .parse::<f64>()
            .map_err(|_| format!("--{flag}: `{text}` is not a number or a quantity with a unit"))?,
        Err(message) => return Err(format!("--{flag}: {message}")),
    };
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(format!("--{flag}: must be > 0, got `{text}`"))
    }
}

/// A gauge signal: `(time, strain)` samples, SI.
pub type Signal = Vec<(f64, f64)>;

/// The gauge signals of a gauges CSV, SI, compressive positive (`tension_positive` negates).
pub fn read_gauges(
    path: &Path,
    text: &str,
    tension_positive: bool,
) -> Result<(Signal, Signal), String> {
    const COLUMNS: [&str; 3] = ["time", "incident", "transmitted"];
    let mut scale = [1.0; 3];
    let mut header_seen = false;
    let (mut incident, mut transmitted) = (Vec::new(), Vec::new());
    let sign = if tension_positive { -1.0 } else { 1.0 };
    for (index, raw) in text.lines().enumerate() {
        let line = raw.trim();
        let at = |field: &str, message: String| {
            format!(
                "{}:{}: field `{field}`: {message}",
                path.display(),
                index + 1
            )
        };
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        if !header_seen {
            let parsed = cells
                .iter()
                .map(|c| header_cell(c))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|m| at("", m))?;
            let names: Vec<&str> = parsed.iter().map(|(n, _)| *n).collect();
            if names != COLUMNS {
                return Err(at(
                    "",
                    format!(
                        "expected the header `{}` (a column may carry a unit: `time [us]`)",
                        COLUMNS.join(",")
                    ),
                ));
            }
            for (k, (name, unit)) in parsed.iter().enumerate() {
                if let Some(unit) = unit {
                    let expected = if k == 0 {
                        Dimension::Time
                    } else {
                        Dimension::Dimensionless
                    };
                    if unit.dimension != expected {
                        return Err(at(name, format!("the unit is not {}", expected.name())));
                    }
                    scale[k] = unit.to_si(1.0);
                }
            }
            header_seen = true;
            continue;
        }
        if cells.len() != 3 {
            return Err(at("", format!("{} cells, expected 3", cells.len())));
        }
        let mut values = [0.0; 3];
        for k in 0..3 {
            let value: f64 = cells[k]
                .parse()
                .map_err(|_| at(COLUMNS[k], format!("`{}` is not a number", cells[k])))?;
            if !value.is_finite() {
                return Err(at(COLUMNS[k], "must be finite".into()));
            }
            values[k] = value * scale[k];
        }
        if let Some(&(previous, _)) = incident.last() {
            if values[0] <= previous {
                return Err(at("time", "times must increase".into()));
            }
        }
        incident.push((values[0], sign * values[1]));
        transmitted.push((values[0], sign * values[2]));
    }
    if incident.len() < 3 {
        return Err(format!(
            "{}: fewer than 3 samples (is the header `time,incident,transmitted` there?)",
            path.display()
        ));
    }
    Ok((incident, transmitted))
}

fn analyse(args: &AnalyseShpbArgs) -> Result<(), String> {
    let analysis = match args.analysis.as_str() {
        "1-wave" => Analysis::OneWave,
        "2-wave" => Analysis::TwoWave,
        "3-wave" => Analysis::ThreeWave,
        other => {
            return Err(format!(
                "--analysis: `{other}` is not 1-wave, 2-wave or 3-wave"
            ))
        }
    };
    if !(args.uncertainty > 0.0 && args.uncertainty < 1.0) {
        return Err(format!(
            "--uncertainty: a fraction in (0, 1), got {}",
            args.uncertainty
        ));
    }
    let modulus = quantity("bar-modulus", &args.bar_modulus, Dimension::Stress)?;
    let density = quantity("bar-density", &args.bar_density, Dimension::Density)?;
    let bar_diameter = quantity("bar-diameter", &args.bar_diameter, Dimension::Length)?;
    let specimen_diameter = quantity(
        "specimen-diameter",
        &args.specimen_diameter,
        Dimension::Length,
    )?;
    let specimen_length = quantity("specimen-length", &args.specimen_length, Dimension::Length)?;
    let d_i = quantity("incident-gauge", &args.incident_gauge, Dimension::Length)?;
    let d_t = quantity(
        "transmitter-gauge",
        &args.transmitter_gauge,
        Dimension::Length,
    )?;
    if specimen_diameter > bar_diameter {
        return Err("--specimen-diameter: larger than the bar".into());
    }
    let text = std::fs::read_to_string(&args.gauges)
        .map_err(|e| format!("{}: {e}", args.gauges.display()))?;
    let (incident, transmitted) = read_gauges(&args.gauges, &text, args.tension_positive)?;
    let bar = KolskyBar {
        young_modulus: modulus,
        wave_speed: libm::sqrt(modulus / density),
        area_ratio: (bar_diameter / specimen_diameter) * (bar_diameter / specimen_diameter),
        specimen_length,
    };
    let (waves, chosen) = analyse_recorded(&bar, &incident, &transmitted, (d_i, d_t), analysis)
        .map_err(|e| format!("{}: {e}", args.gauges.display()))?;
    let all: Vec<StressStrain> = [Analysis::OneWave, Analysis::TwoWave, Analysis::ThreeWave]
        .iter()
        .map(|a| bar.analyse(&waves, *a))
        .collect();

    let (start, end) = incident_pulse(&incident).unwrap_or_default();
    let mut series = format!(
        "# Kolsky analysis by `stoss analyse-shpb` of {}\n# bars E {modulus:e} Pa, rho \
         {density:e} kg/m^3 (c0 {:.1} m/s), diameter {bar_diameter:e} m; specimen \
         {specimen_diameter:e} x {specimen_length:e} m; gauges at {d_i:e} and {d_t:e} m\n\
         # incident pulse at the gauge {start:e} to {end:e} s; time at the specimen faces; \
         stress compressive positive\n\
         time [s],strain_1w,strain_rate_1w [1/s],stress_1w [Pa],strain_2w,strain_rate_2w \
         [1/s],stress_2w [Pa],strain_3w,strain_rate_3w [1/s],stress_3w [Pa]\n",
        args.gauges.display(),
        bar.wave_speed
    );
    for k in 0..waves.time.len() {
        let _ = write!(series, "{:e}", waves.time[k]);
        for a in &all {
            let _ = write!(
                series,
                ",{:e},{:e},{:e}",
                a.strain[k], a.strain_rate[k], a.stress[k]
            );
        }
        series.push('\n');
    }
    let mut recording = format!(
        "# engineering stress-strain (loading branch, {} analysis) of {} by `stoss \
         analyse-shpb`;\n# mean strain rate {:.4e} /s; uncertainty {} x |value| as given by \
         --uncertainty\nquantity,position,value,uncertainty\n",
        args.analysis,
        args.gauges.display(),
        chosen.mean_strain_rate(),
        args.uncertainty
    );
    let curve = chosen.curve();
    // At most ~100 points, evenly in strain.
    let stride = (curve.len() / 100).max(1);
    for (strain, stress) in curve.iter().step_by(stride) {
        let _ = writeln!(
            recording,
            "engineering_stress,{strain:e},{stress:e},{:e}",
            args.uncertainty * stress.abs()
        );
    }
    let series_path = args.output.with_extension("csv");
    let recording_path = args.output.with_extension("recording.csv");
    std::fs::write(&series_path, series).map_err(|e| format!("{}: {e}", series_path.display()))?;
    std::fs::write(&recording_path, recording)
        .map_err(|e| format!("{}: {e}", recording_path.display()))?;
    let peak = |a: &StressStrain| a.stress.iter().copied().fold(0.0, f64::max);
    say!(
        "mean strain rate {:.4e} /s, largest engineering strain {:.4}",
        chosen.mean_strain_rate(),
        chosen.max_strain()
    );
    say!(
        "peak engineering stress: 1-wave {:.4e} Pa, 2-wave {:.4e} Pa, 3-wave {:.4e} Pa \
         (front and back faces apart by {:.1} %: equilibrium)",
        peak(&all[0]),
        peak(&all[1]),
        peak(&all[2]),
        100.0 * (peak(&all[1]) - peak(&all[0])).abs() / peak(&all[2]).max(f64::MIN_POSITIVE)
    );
    say!(
        "wrote {} and {}",
        series_path.display(),
        recording_path.display()
    );
    super::output::json(&serde_json::json!({
        "command": "analyse-shpb",
        "mean_strain_rate": chosen.mean_strain_rate(),
        "largest_engineering_strain": chosen.max_strain(),
        "peak_engineering_stress": {
            "one_wave": peak(&all[0]),
            "two_wave": peak(&all[1]),
            "three_wave": peak(&all[2]),
        },
        "series": series_path,
        "recording": recording_path,
    }));
    Ok(())
}
