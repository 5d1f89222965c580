//! Any J2 model as tabulated flow-stress cards: the flow stress `sigma_y(eps_p, deps_p/dt, T)`
//! sampled on one grid and written two ways. This carries every stoss model, coupled ones
//! (Zerilli-Armstrong, the diagnosis' rate-temperature term) included, into a code that has
//! no card for it.
//!
//! - [`ls_dyna`]: LS-DYNA `*MAT_TABULATED_JOHNSON_COOK` (*MAT_224), a `*DEFINE_TABLE_3D` (one
//!   `*DEFINE_TABLE_2D` per temperature, one `*DEFINE_CURVE` of flow stress against plastic
//!   strain per plastic strain rate), which `LCK1` names. The reading it assumes (LS-DYNA
//!   manual vol. II, *MAT_224 and *DEFINE_TABLE): the 2D tables' abscissae are natural
//!   logarithms of the plastic strain rate (their first value is negative, which tells
//!   LS-DYNA so); interpolation is linear in plastic strain along a curve (extrapolated from
//!   its last segment), linear in `ln(rate)` between curves and linear in temperature between
//!   tables; rates and temperatures outside the table take the nearest end.
//! - [`abaqus`]: Abaqus/Explicit `*PLASTIC, RATE=` tables, one per plastic strain rate, each
//!   with a temperature column, under `*MATERIAL, STRAIN RATE INTERPOLATION=LOGARITHMIC`. The
//!   reading it assumes (Abaqus keywords reference, *MATERIAL and *PLASTIC; Analysis User's
//!   Guide, "Rate-dependent yield"): the yield stress is interpolated linearly in plastic
//!   strain and temperature within a table, in `ln(rate)` between the rate tables, and is
//!   held constant outside the given plastic strains, temperatures and rates. Abaqus/Explicit
//!   also regularizes tabular data to within `RTOL` (default 3 %) before the analysis; that
//!   is not part of the stated error. Abaqus/Standard interpolates between the rate tables
//!   linearly in the rate, so the stated error holds for Abaqus/Explicit only.
//!
//! [`FlowTable::interpolate`] implements both readings ([`Reading`]); they differ only beyond
//! the largest plastic strain. Each card states the sampled ranges and the largest
//! interpolation error against the model, measured at the midpoints of every grid cell.

use super::units::{CardOptions, CardUnits, Quantity};
use super::{bulk_modulus, field, line, young_and_poisson};
use crate::input::material::MaterialFile;
use std::fmt::Write as _;
use stoss_kernel::parameters::ConstantPaths;
use stoss_kernel::strength::Strength;
use stoss_kernel::Heating;

/// Flow stress on a grid of plastic strain, `ln(rate)` and temperature.
#[derive(Clone, Debug, PartialEq)]
pub struct FlowTable {
    /// Plastic strains, increasing from 0.
    pub plastic_strains: Vec<f64>,
    /// Natural logarithms of the plastic strain rates (1/s), increasing.
    pub ln_rates: Vec<f64>,
    /// Temperatures (K), increasing.
    pub temperatures: Vec<f64>,
    /// `values[t][r][e]`: the flow stress (Pa) at temperature `t`, rate `r`, strain `e`.
    pub values: Vec<Vec<Vec<f64>>>,
}

/// How a code reads a [`FlowTable`] between and beyond its points (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reading {
    /// LS-DYNA *MAT_224: a curve is extended from its last segment beyond the largest
    /// plastic strain.
    LsDyna,
    /// Abaqus/Explicit `*PLASTIC, RATE=` with logarithmic rate interpolation: the yield
    /// stress is held at its last value beyond the largest plastic strain.
    AbaqusExplicit,
}

/// Plastic strain rates sampled: 1e-4 to 1e5 /s, two per decade, plus the model's own
/// reference rates inside that range (where a rate term has a kink).
const RATE_DECADES: (i32, i32) = (-4, 5);
/// Homologous temperatures sampled between the reference and melting temperatures.
const HOMOLOGOUS: [f64; 17] = [
    0.0, 0.01, 0.03, 0.06, 0.1, 0.15, 0.2, 0.26, 0.33, 0.4, 0.48, 0.56, 0.64, 0.72, 0.8, 0.9, 1.0,
];
/// The temperature range used when the model has no melting temperature (Zerilli-Armstrong,
/// which softens through `exp(-C3 T)`): 293 K to 1800 K.
const DEFAULT_TEMPERATURES: (f64, f64) = (293.0, 1800.0);
/// Largest plastic strain sampled (beyond it LS-DYNA extends a curve's last segment and
/// Abaqus holds its last value).
const LARGEST_PLASTIC_STRAIN: f64 = 5.0;

/// The reference and melting temperature of the model's thermal term, if it has them.
fn temperature_range(strength: &Strength) -> (f64, f64) {
    match strength {
        Strength::Composed(model) => model
            .thermal
            .temperature_limits()
            .unwrap_or(DEFAULT_TEMPERATURES),
        Strength::ZerilliArmstrong(_) => DEFAULT_TEMPERATURES,
        Strength::PrestonTonksWallace(model) => (DEFAULT_TEMPERATURES.0, model.melting_temperature),
        Strength::KhanHuangLiang(model) => (model.reference_temperature, model.melting_temperature),
        Strength::VoceKocks(_) | Strength::MechanicalThresholdStress(_) => DEFAULT_TEMPERATURES,
    }
}

/// The temperatures the table samples: the homologous fractions [`HOMOLOGOUS`] of the model's
/// range, and a thermal drop's knots inside it, in increasing order.
fn sampled_temperatures(strength: &Strength) -> Vec<f64> {
    let (cold, hot) = temperature_range(strength);
    let mut temperatures: Vec<f64> = HOMOLOGOUS.iter().map(|h| cold + h * (hot - cold)).collect();
    if let Strength::Composed(model) = strength {
        if let Some(knots) = model.thermal.knots() {
            temperatures.extend(knots.iter().filter(|t| **t > cold && **t < hot));
            temperatures.sort_by(f64::total_cmp);
            temperatures.dedup();
        }
    }
    temperatures
}

/// The reference rates among the model's constants (unit 1/s), which a rate term has a kink
/// or a knee at.
fn reference_rates(file: &MaterialFile) -> Vec<f64> {
    file.strength
        .constants()
        .into_iter()
        .filter(|(_, p)| p.unit == "1/s")
        .filter_map(|(name, _)| file.strength.get(&name))
        .collect()
}

impl FlowTable {
    /// Sample `strength` on stoss's grid: plastic strain 0 and `1e-6 * 2^(k/2)` up to 5;
    /// rates two per decade from 1e-4 to 1e5 /s with `extra_rates` inserted; temperatures at
    /// the homologous fractions [`HOMOLOGOUS`] of the model's range and a thermal drop's
    /// knots.
    pub fn sample(strength: &Strength, extra_rates: &[f64]) -> Self {
        let mut plastic_strains = vec![0.0];
        let mut k = 0;
        loop {
            let strain = 1.0e-6 * libm::exp2(f64::from(k) / 2.0);
            plastic_strains.push(strain.min(LARGEST_PLASTIC_STRAIN));
            if strain >= LARGEST_PLASTIC_STRAIN {
                break;
            }
            k += 1;
        }
        let mut ln_rates: Vec<f64> = (2 * RATE_DECADES.0..=2 * RATE_DECADES.1)
            .map(|half| f64::from(half) / 2.0 * std::f64::consts::LN_10)
            .collect();
        let (low, high) = (ln_rates[0], ln_rates[ln_rates.len() - 1]);
        for rate in extra_rates {
            let ln = libm::log(*rate);
            if rate.is_finite() && *rate > 0.0 && ln > low && ln < high {
                ln_rates.push(ln);
            }
        }
        ln_rates.sort_by(f64::total_cmp);
        ln_rates.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        let temperatures = sampled_temperatures(strength);
        let values = temperatures
            .iter()
            .map(|&t| {
                ln_rates
                    .iter()
                    .map(|&ln| {
                        let at = strength.at_temperature(t);
                        let rate = libm::exp(ln);
                        plastic_strains
                            .iter()
                            .map(|&e| at.flow_stress(e, rate).value)
                            .collect()
                    })
                    .collect()
            })
            .collect();
        Self {
            plastic_strains,
            ln_rates,
            temperatures,
            values,
        }
    }

    /// The flow stress as a code reads the table (see the module docs).
    pub fn interpolate(
        &self,
        reading: Reading,
        plastic_strain: f64,
        rate: f64,
        temperature: f64,
    ) -> f64 {
        let ln_rate = if rate > 0.0 {
            libm::log(rate)
        } else {
            f64::NEG_INFINITY
        };
        let (t0, t1, wt) = bracket(&self.temperatures, temperature);
        let (r0, r1, wr) = bracket(&self.ln_rates, ln_rate);
        let curve = |t: usize, r: usize| {
            along_curve(
                reading,
                &self.plastic_strains,
                &self.values[t][r],
                plastic_strain,
            )
        };
        let at_t0 = (1.0 - wr) * curve(t0, r0) + wr * curve(t0, r1);
        let at_t1 = (1.0 - wr) * curve(t1, r0) + wr * curve(t1, r1);
        (1.0 - wt) * at_t0 + wt * at_t1
    }

    /// The largest difference between the table and `strength` at the midpoints of every
    /// grid cell (geometric in plastic strain, arithmetic in `ln(rate)` and temperature):
    /// `(relative error, where)` over the points below 0.9 of the temperature range (near
    /// melt the flow stress tends to 0 and a relative error says nothing), and the largest
    /// absolute error (Pa) anywhere. The points lie inside the table, where every
    /// [`Reading`] agrees.
    pub fn largest_error(&self, strength: &Strength) -> InterpolationError {
        let mids = |x: &[f64], geometric: bool| -> Vec<f64> {
            x.windows(2)
                .map(|w| {
                    if geometric && w[0] > 0.0 {
                        libm::sqrt(w[0] * w[1])
                    } else {
                        0.5 * (w[0] + w[1])
                    }
                })
                .chain(x.iter().copied())
                .collect()
        };
        let strains = mids(&self.plastic_strains, true);
        let ln_rates = mids(&self.ln_rates, false);
        let temperatures = mids(&self.temperatures, false);
        let (cold, hot) = (
            self.temperatures[0],
            self.temperatures[self.temperatures.len() - 1],
        );
        let mut worst = InterpolationError::default();
        for &t in &temperatures {
            let at = strength.at_temperature(t);
            for &ln in &ln_rates {
                let rate = libm::exp(ln);
                for &e in &strains {
                    let model = at.flow_stress(e, rate).value;
                    let table = self.interpolate(Reading::LsDyna, e, rate, t);
                    let absolute = (table - model).abs();
                    if absolute > worst.absolute {
                        worst.absolute = absolute;
                    }
                    if t <= cold + 0.9 * (hot - cold) && model > 0.0 {
                        let relative = absolute / model;
                        if relative > worst.relative {
                            worst.relative = relative;
                            worst.at = (e, rate, t);
                        }
                    }
                }
            }
        }
        worst
    }

    /// This table, read from a card written in `units`, in SI (stresses in Pa, rates in 1/s).
    pub fn to_si(&self, units: &CardUnits) -> Self {
        let stress = units.size(Quantity::Stress);
        let ln_time = libm::log(units.size(Quantity::Time));
        Self {
            plastic_strains: self.plastic_strains.clone(),
            ln_rates: self.ln_rates.iter().map(|r| r - ln_time).collect(),
            temperatures: self.temperatures.clone(),
            values: self
                .values
                .iter()
                .map(|t| {
                    t.iter()
                        .map(|r| r.iter().map(|v| v * stress).collect())
                        .collect()
                })
                .collect(),
        }
    }

    /// Read the tables back from a card written by [`ls_dyna`]: the `*DEFINE_TABLE_3D`
    /// named by `LCK1`, its 2D tables and their curves, with LS-DYNA's column rules (10
    /// columns for ids, 20 for values).
    pub fn read_ls_dyna(card: &str) -> Result<Self, String> {
        let blocks = keyword_blocks(card);
        let block = |keyword: &str, id: i64| -> Result<&Vec<&str>, String> {
            blocks
                .iter()
                .find(|(k, lines)| {
                    k == keyword
                        && lines
                            .first()
                            .and_then(|l| super::read_fields(l, &[10]).ok())
                            .is_some_and(|v| v[0] as i64 == id)
                })
                .map(|(_, lines)| lines)
                .ok_or_else(|| format!("no {keyword} with id {id}"))
        };
        let mat = blocks
            .iter()
            .find(|(k, _)| k == "*MAT_TABULATED_JOHNSON_COOK")
            .ok_or("no *MAT_TABULATED_JOHNSON_COOK")?;
        let lck1 = super::read_fields(mat.1.get(1).ok_or("no card 2")?, &[10; 6])?[0] as i64;
        let pairs = |lines: &[&str]| -> Result<Vec<(f64, f64)>, String> {
            lines[1..]
                .iter()
                .map(|l| super::read_fields(l, &[20, 20]).map(|v| (v[0], v[1])))
                .collect()
        };
        let by_temperature = pairs(block("*DEFINE_TABLE_3D", lck1)?)?;
        let mut table = FlowTable {
            plastic_strains: Vec::new(),
            ln_rates: Vec::new(),
            temperatures: Vec::new(),
            values: Vec::new(),
        };
        for (temperature, table_id) in by_temperature {
            let by_rate = pairs(block("*DEFINE_TABLE_2D", table_id as i64)?)?;
            let mut curves = Vec::new();
            let mut ln_rates = Vec::new();
            for (ln_rate, curve_id) in by_rate {
                let points = pairs(block("*DEFINE_CURVE", curve_id as i64)?)?;
                table.plastic_strains = points.iter().map(|p| p.0).collect();
                curves.push(points.iter().map(|p| p.1).collect());
                ln_rates.push(ln_rate);
            }
            table.ln_rates = ln_rates;
            table.temperatures.push(temperature);
            table.values.push(curves);
        }
        Ok(table)
    }
}

impl FlowTable {
    /// Read the tables back from a card written by [`abaqus`], as Abaqus reads comma-separated
    /// data lines: one `*PLASTIC, RATE=` table per rate, rows of yield stress, plastic strain
    /// and temperature, grouped by temperature. The rates come back as `ln(rate)` of the
    /// written rate.
    pub fn read_abaqus(card: &str) -> Result<Self, String> {
        let mut table = FlowTable {
            plastic_strains: Vec::new(),
            ln_rates: Vec::new(),
            temperatures: Vec::new(),
            values: Vec::new(),
        };
        // rows[r] = (stress, strain, temperature) of the r-th rate table.
        let mut rows: Vec<Vec<[f64; 3]>> = Vec::new();
        let mut in_plastic = false;
        for (number, line) in card.lines().enumerate() {
            let number = number + 1;
            if line.starts_with("**") {
                continue;
            }
            if let Some(keyword) = line.strip_prefix('*') {
                let mut parts = keyword.split(',').map(str::trim);
                in_plastic = parts
                    .next()
                    .is_some_and(|k| k.eq_ignore_ascii_case("PLASTIC"));
                if in_plastic {
                    let rate = parts
                        .find_map(|p| p.strip_prefix("RATE="))
                        .ok_or(format!("line {number}: *PLASTIC without RATE="))?
                        .parse::<f64>()
                        .map_err(|_| format!("line {number}: RATE is not a number"))?;
                    table.ln_rates.push(libm::log(rate));
                    rows.push(Vec::new());
                }
                continue;
            }
            if in_plastic {
                let values: Vec<f64> = line
                    .split(',')
                    .map(|f| f.trim().parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| format!("line {number}: `{line}` is not three numbers"))?;
                let [stress, strain, temperature] = values[..] else {
                    return Err(format!("line {number}: `{line}` is not three numbers"));
                };
                if let Some(current) = rows.last_mut() {
                    current.push([stress, strain, temperature]);
                }
            }
        }
        let first = rows.first().ok_or("no *PLASTIC, RATE= table")?;
        for row in first {
            if !table.temperatures.contains(&row[2]) {
                table.temperatures.push(row[2]);
            }
        }
        table.plastic_strains = first
            .iter()
            .filter(|row| row[2] == table.temperatures[0])
            .map(|row| row[1])
            .collect();
        let per_table = table.temperatures.len() * table.plastic_strains.len();
        if let Some(r) = rows.iter().position(|rows| rows.len() != per_table) {
            return Err(format!("rate table {r} is not {per_table} rows"));
        }
        table.values = (0..table.temperatures.len())
            .map(|t| {
                rows.iter()
                    .map(|rate| {
                        rate[t * table.plastic_strains.len()..(t + 1) * table.plastic_strains.len()]
                            .iter()
                            .map(|row| row[0])
                            .collect()
                    })
                    .collect()
            })
            .collect();
        Ok(table)
    }
}

/// The largest interpolation error of a [`FlowTable`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InterpolationError {
    /// Largest relative error below 0.9 of the temperature range.
    pub relative: f64,
    /// Where: plastic strain, rate (1/s), temperature (K).
    pub at: (f64, f64, f64),
    /// Largest absolute error anywhere (Pa).
    pub absolute: f64,
}

/// The keyword blocks of a card: the keyword and its data lines (comments dropped).
fn keyword_blocks(card: &str) -> Vec<(String, Vec<&str>)> {
    let mut blocks: Vec<(String, Vec<&str>)> = Vec::new();
    for line in card.lines() {
        if line.starts_with('$') {
            continue;
        }
        if let Some(keyword) = line.strip_prefix('*') {
            blocks.push((format!("*{}", keyword.trim()), Vec::new()));
        } else if let Some(last) = blocks.last_mut() {
            last.1.push(line);
        }
    }
    blocks
}

/// Indices of the points around `x` in increasing `points` and the weight of the upper one;
/// outside, the nearest end.
fn bracket(points: &[f64], x: f64) -> (usize, usize, f64) {
    let last = points.len() - 1;
    if x.is_nan() || x <= points[0] {
        return (0, 0, 0.0);
    }
    if x >= points[last] {
        return (last, last, 0.0);
    }
    let upper = points.partition_point(|p| *p <= x);
    let lower = upper - 1;
    (
        lower,
        upper,
        (x - points[lower]) / (points[upper] - points[lower]),
    )
}

/// Linear interpolation along a curve; beyond its end, extrapolated from its last segment
/// (LS-DYNA) or held at its last value (Abaqus).
fn along_curve(reading: Reading, x: &[f64], y: &[f64], at: f64) -> f64 {
    let last = x.len() - 1;
    if at >= x[last] && reading == Reading::AbaqusExplicit {
        return y[last];
    }
    if at >= x[last] {
        let slope = (y[last] - y[last - 1]) / (x[last] - x[last - 1]);
        return y[last] + slope * (at - x[last]);
    }
    let (i, j, w) = bracket(x, at);
    (1.0 - w) * y[i] + w * y[j]
}

/// Id of the 3D table (`LCK1`); 2D tables are `1000 (t + 1)`, curves `1000 (t + 1) + r + 1`.
const TABLE_3D: usize = 100;

/// What both tabulated cards hold: the elastic constants, the sampled table, its error and
/// the heating.
struct Sampled {
    young: f64,
    poisson: f64,
    table: FlowTable,
    error: InterpolationError,
    /// The Taylor-Quinney factor (0 if isothermal).
    taylor_quinney: f64,
    /// The card's comment lines (without the comment marker): the material, units, sampled
    /// ranges, the stated error and, if any, the heating transition the card cannot hold.
    summary: Vec<String>,
}

/// Sample `file`'s flow stress (`None` if the EoS gives no bulk modulus for `E`, `nu`); the
/// summary names `units`.
fn sampled(file: &MaterialFile, units: &CardUnits) -> Option<Sampled> {
    let bulk = bulk_modulus(file)?;
    let (young, poisson) = young_and_poisson(bulk, file.shear_modulus);
    let strength = file.strength.strength();
    let table = FlowTable::sample(&strength, &reference_rates(file));
    let error = table.largest_error(&strength);
    let (taylor_quinney, heating_note) = match file.heating {
        Heating::Isothermal => (0.0, None),
        Heating::Adiabatic { taylor_quinney } => (taylor_quinney, None),
        Heating::Transition {
            taylor_quinney,
            isothermal_rate,
            adiabatic_rate,
        } => (
            taylor_quinney,
            Some(format!(
                "NOTE: stoss heats this material only above {isothermal_rate:e} /s (fully above \
                 {adiabatic_rate:e} /s); the card's heat fraction heats at every rate."
            )),
        ),
    };
    let (first_rate, last_rate) = (
        libm::exp(table.ln_rates[0]),
        libm::exp(table.ln_rates[table.ln_rates.len() - 1]),
    );
    let mut summary = vec![
        format!("stoss tabulated material: {}", file.name),
        units.header(),
        format!(
            "flow stress of the stoss model sampled at plastic strain 0..{LARGEST_PLASTIC_STRAIN} ({} points),",
            table.plastic_strains.len()
        ),
        format!(
            "plastic strain rate {first_rate:.3e}..{last_rate:.3e} /s in SI ({} rates), temperature {:.1}..{:.1} K ({} temperatures).",
            table.ln_rates.len(),
            table.temperatures[0],
            table.temperatures[table.temperatures.len() - 1],
            table.temperatures.len(),
        ),
        format!(
            "largest interpolation error against the model at the cell midpoints: {:.3} % \
             (at plastic strain {:.3e}, {:.3e} /s, {:.1} K; below 0.9 of the temperature range), \
             {:.3e} Pa anywhere.",
            100.0 * error.relative,
            error.at.0,
            error.at.1,
            error.at.2,
            error.absolute,
        ),
    ];
    summary.extend(heating_note);
    Some(Sampled {
        young,
        poisson,
        table,
        error,
        taylor_quinney,
        summary,
    })
}

/// The LS-DYNA *MAT_224 card and the table it holds (`None` if the EoS gives no bulk modulus
/// for `E`, `PR`).
///
/// In `options`' units: stresses, the density, the specific heat, and the rates of the 2D
/// tables' abscissae (`ln` of the rate in the card's time unit); the returned table is SI.
pub fn ls_dyna(
    file: &MaterialFile,
    options: &CardOptions,
) -> Option<(String, FlowTable, InterpolationError)> {
    let units = &options.units;
    let Sampled {
        young,
        poisson,
        table,
        error,
        taylor_quinney: beta,
        summary,
    } = sampled(file, units)?;
    let u = |value: f64, quantity: Quantity| units.from_si(value, quantity);
    let ln_time = libm::log(units.size(Quantity::Time));
    let cold = table.temperatures[0];
    let mut text = String::new();
    for line in &summary {
        let _ = writeln!(text, "$ {line}");
    }
    let _ = writeln!(
        text,
        "$ curves are extended beyond the largest plastic strain; abscissae of the 2D tables are ln(rate)."
    );
    let _ = writeln!(
        text,
        "*MAT_TABULATED_JOHNSON_COOK\n$      MID        RO         E        PR        CP        TR      BETA    NUMINT\n{}",
        line(
            &[
                f64::from(options.material_id),
                u(file.density, Quantity::Density),
                u(young, Quantity::Stress),
                poisson,
                u(file.specific_heat, Quantity::SpecificHeat),
                cold,
                beta,
                1.0
            ],
            10
        )
    );
    let _ = writeln!(
        text,
        "$     LCK1      LCKT       LCF       LCG       LCH       LCI\n{}",
        line(&[TABLE_3D as f64, 0.0, 0.0, 0.0, 0.0, 0.0], 10)
    );
    let _ = writeln!(
        text,
        "*DEFINE_TABLE_3D\n$     TBID       SFA      OFFA\n{}\n$        temperature (K)      2D table id",
        line(&[TABLE_3D as f64], 10)
    );
    for (t, temperature) in table.temperatures.iter().enumerate() {
        let _ = writeln!(
            text,
            "{}",
            line(&[*temperature, (1000 * (t + 1)) as f64], 20)
        );
    }
    for (t, temperature) in table.temperatures.iter().enumerate() {
        let id = 1000 * (t + 1);
        let _ = writeln!(
            text,
            "*DEFINE_TABLE_2D\n$ {temperature:.1} K\n{}\n$    ln(plastic rate)         curve id",
            line(&[id as f64], 10)
        );
        for r in 0..table.ln_rates.len() {
            let _ = writeln!(
                text,
                "{}",
                line(&[table.ln_rates[r] + ln_time, (id + r + 1) as f64], 20)
            );
        }
        for (r, ln_rate) in table.ln_rates.iter().enumerate() {
            let _ = writeln!(
                text,
                "*DEFINE_CURVE\n$ {temperature:.1} K, {:.4e} /s\n{}\n$       plastic strain   flow stress ({})",
                libm::exp(*ln_rate),
                line(&[(id + r + 1) as f64], 10),
                units.stress_name()
            );
            for (e, value) in table.plastic_strains.iter().zip(&table.values[t][r]) {
                let _ = writeln!(
                    text,
                    "{}{}",
                    field(*e, 20),
                    field(u(*value, Quantity::Stress), 20)
                );
            }
        }
    }
    Some((text, table, error))
}

/// The Abaqus/Explicit card (`*PLASTIC, RATE=` tables with a temperature column) and the
/// table it holds (`None` if the EoS gives no bulk modulus for `E`, `nu`). Every number is
/// written in its shortest exact form, so the card holds the sampled table to the last bit.
///
/// In `options`' units (stresses, density, specific heat, the tables' rates); the returned
/// table is SI.
pub fn abaqus(
    file: &MaterialFile,
    options: &CardOptions,
) -> Option<(String, FlowTable, InterpolationError)> {
    let units = &options.units;
    let Sampled {
        young,
        poisson,
        table,
        error,
        taylor_quinney,
        summary,
    } = sampled(file, units)?;
    let u = |value: f64, quantity: Quantity| units.from_si(value, quantity);
    let mut text = String::new();
    for line in &summary {
        let _ = writeln!(text, "** {line}");
    }
    let _ = writeln!(
        text,
        "** Abaqus/Explicit reading: linear in plastic strain and temperature, logarithmic in rate\n\
         ** (STRAIN RATE INTERPOLATION below), held constant outside the tables. Abaqus/Standard\n\
         ** interpolates linearly in rate; the stated error is for Abaqus/Explicit.\n\
         ** Heating needs an adiabatic step (*DYNAMIC, EXPLICIT, ADIABATIC) and an initial\n\
         ** temperature (*INITIAL CONDITIONS, TYPE=TEMPERATURE, from {:.1} K).",
        table.temperatures[0]
    );
    let _ = writeln!(
        text,
        "*MATERIAL, NAME={}, STRAIN RATE INTERPOLATION=LOGARITHMIC\n*DENSITY\n{:e}\n*ELASTIC\n{:e}, {:e}",
        options.name,
        u(file.density, Quantity::Density),
        u(young, Quantity::Stress),
        poisson
    );
    if taylor_quinney > 0.0 {
        let _ = writeln!(
            text,
            "*SPECIFIC HEAT\n{:e}\n*INELASTIC HEAT FRACTION\n{taylor_quinney:e}",
            u(file.specific_heat, Quantity::SpecificHeat)
        );
    }
    for (r, ln_rate) in table.ln_rates.iter().enumerate() {
        // A rate a few ulp from a round number is written round (1e-4, not
        // exp(ln 1e-4) = 9.999999999999991e-5).
        let exact = u(libm::exp(*ln_rate), Quantity::Rate);
        let round: f64 = format!("{exact:.11e}").parse().unwrap_or(exact);
        let rate = if (round - exact).abs() <= 1e-14 * exact {
            round
        } else {
            exact
        };
        let _ = writeln!(
            text,
            "*PLASTIC, RATE={rate:e}\n** yield stress ({}), plastic strain, temperature (K)",
            units.stress_name()
        );
        for (t, temperature) in table.temperatures.iter().enumerate() {
            for (e, value) in table.plastic_strains.iter().zip(&table.values[t][r]) {
                let _ = writeln!(
                    text,
                    "{:e}, {e:e}, {temperature:e}",
                    u(*value, Quantity::Stress)
                );
            }
        }
    }
    Some((text, table, error))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::material::StrengthSpec;
    use stoss_kernel::strength::{
        ComposedStrength, Hardening, JohnsonCook, ModifiedJohnsonCook, RateTerm,
        TwoRateJohnsonCook, ZerilliArmstrong,
    };
    use stoss_kernel::{update, MaterialState, StepInput};

    /// One model of each family stoss has, on the bundled 4340 file's elasticity and EoS.
    fn families() -> Vec<(&'static str, MaterialFile)> {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fixtures/materials/4340-jc.toml");
        let (base, _) = crate::input::material::load(&path).unwrap();
        let jc = JohnsonCook::STEEL_4340;
        let mut upturn = jc.composed();
        upturn.rate = RateTerm::LogUpturn {
            rate_sensitivity: 0.014,
            reference_rate: 1.0,
            upturn_exponent: 0.08,
            upturn_rate: 2.0e3,
        };
        let mut coupled = jc.composed();
        coupled.rate = RateTerm::LogThermal {
            rate_sensitivity: 0.014,
            reference_rate: 1.0,
            coupling: 2.0,
            reference_temperature: 298.0,
            melting_temperature: 1793.0,
        };
        let voce = ComposedStrength {
            hardening: Hardening::Voce2 {
                yield_stress: 700.0e6,
                saturation_stress_1: 300.0e6,
                saturation_rate_1: 20.0,
                saturation_stress_2: 100.0e6,
                saturation_rate_2: 800.0,
            },
            rate: RateTerm::CowperSymonds {
                rate_constant: 4.0e4,
                exponent: 5.0,
            },
            thermal: stoss_kernel::strength::ThermalTerm::Linear {
                reference_temperature: 298.0,
                melting_temperature: 1793.0,
            },
        };
        let specs = [
            ("johnson-cook", StrengthSpec::JohnsonCook(jc)),
            (
                "zerilli-armstrong-bcc",
                StrengthSpec::ZerilliArmstrong(ZerilliArmstrong {
                    athermal_stress: 400.0e6,
                    ..ZerilliArmstrong::ARMCO_IRON
                }),
            ),
            (
                "modified-johnson-cook",
                StrengthSpec::ModifiedJohnsonCook(ModifiedJohnsonCook {
                    yield_stress: 750.0e6,
                    hardening_modulus: 300.0e6,
                    hardening_exponent: 0.4,
                    saturation_stress_1: 150.0e6,
                    saturation_rate_1: 30.0,
                    saturation_stress_2: 50.0e6,
                    saturation_rate_2: 500.0,
                    rate_exponent: 0.012,
                    reference_rate: 1.0e-3,
                    thermal_exponent: 0.8,
                    reference_temperature: 298.0,
                    melting_temperature: 1793.0,
                }),
            ),
            (
                "two-rate-johnson-cook",
                StrengthSpec::TwoRateJohnsonCook(TwoRateJohnsonCook {
                    yield_stress: 750.0e6,
                    hardening_modulus: 300.0e6,
                    hardening_exponent: 0.4,
                    saturation_stress_1: 150.0e6,
                    saturation_rate_1: 30.0,
                    saturation_stress_2: 50.0e6,
                    saturation_rate_2: 500.0,
                    rate_exponent_1: 0.005,
                    reference_rate_1: 1.0e-3,
                    rate_exponent_2: 0.05,
                    reference_rate_2: 3.0e3,
                    thermal_exponent: 1.1,
                    reference_temperature: 298.0,
                    melting_temperature: 1793.0,
                }),
            ),
            ("jc-high-rate-upturn", StrengthSpec::Composed(upturn)),
            (
                "jc-rate-temperature-coupling",
                StrengthSpec::Composed(coupled),
            ),
            ("voce-cowper-symonds-linear", StrengthSpec::Composed(voce)),
            (
                "jc-thermal-drop",
                StrengthSpec::Composed(ComposedStrength {
                    thermal: stoss_kernel::strength::ThermalTerm::HomologousPowerDrop {
                        exponent: 1.03,
                        reference_temperature: 298.0,
                        melting_temperature: 1793.0,
                        drop: 0.25,
                        drop_start_temperature: 840.0,
                        drop_end_temperature: 960.0,
                    },
                    ..upturn
                }),
            ),
        ];
        specs
            .into_iter()
            .map(|(name, strength)| {
                let mut file = base.clone();
                file.strength = strength;
                file.material().unwrap();
                (name, file)
            })
            .collect()
    }

    /// The card of `file` in each format, read back from its text as the target code reads
    /// it, with the table written and the error stated.
    fn cards_read_back(
        file: &MaterialFile,
    ) -> Vec<(Reading, String, FlowTable, FlowTable, InterpolationError)> {
        let (dyna, dyna_written, dyna_error) = ls_dyna(file, &CardOptions::default()).unwrap();
        let (inp, inp_written, inp_error) = abaqus(file, &CardOptions::default()).unwrap();
        vec![
            (
                Reading::LsDyna,
                dyna.clone(),
                FlowTable::read_ls_dyna(&dyna).unwrap(),
                dyna_written,
                dyna_error,
            ),
            (
                Reading::AbaqusExplicit,
                inp.clone(),
                FlowTable::read_abaqus(&inp).unwrap(),
                inp_written,
                inp_error,
            ),
        ]
    }

    #[test]
    fn every_model_read_back_from_its_tabulated_cards_follows_the_kernel_history() {
        // GOAL: a model with no native card (ZA, MJC, TJC, the diagnosis' terms) reaches
        //       LS-DYNA through *MAT_224 and Abaqus/Explicit through *PLASTIC, RATE= tables,
        //       and flows there as it does in stoss.
        // SETUP: one model per family and term; each card written, then read back from its
        //        text with the target format's rules (LS-DYNA columns; Abaqus comma-separated
        //        rows) and interpolated as the code documents; single-element histories
        //        (isochoric tension, adiabatic) at 1e-3, 30 and 5000 /s from 293 K and 700 K
        //        to 50 % strain, through the kernel's update.
        // REFERENCE: the kernel's flow stress at every step's (eps_p, rate, T); the table
        //            agrees within the interpolation error the card states (measured at the
        //            cell midpoints; 1.5x allows for points between them), and that error is
        //            below 1 %.
        for (name, file) in families() {
            for (reading, card, read, written, error) in cards_read_back(&file) {
                let same = |a: &[f64], b: &[f64]| {
                    a.len() == b.len()
                        && a.iter()
                            .zip(b)
                            .all(|(x, y)| (x - y).abs() <= 1e-14 * y.abs())
                };
                let holds = same(&read.plastic_strains, &written.plastic_strains)
                    && same(&read.ln_rates, &written.ln_rates)
                    && same(&read.temperatures, &written.temperatures)
                    && read.values.len() == written.values.len()
                    && read
                        .values
                        .iter()
                        .zip(&written.values)
                        .all(|(a, b)| a.len() == b.len())
                    && read
                        .values
                        .iter()
                        .flatten()
                        .zip(written.values.iter().flatten())
                        .all(|(a, b)| same(a, b));
                assert!(
                    holds,
                    "{name}, {reading:?}: the card holds the sampled table to 15 digits"
                );
                assert!(error.relative < 0.01, "{name}: {error:?}");
                assert!(card.contains(&format!("{:.3} %", 100.0 * error.relative)));
                let material = file.material().unwrap();
                let mut worst: f64 = 0.0;
                for rate in [1.0e-3, 30.0, 5.0e3] {
                    for temperature in [293.0, 700.0] {
                        let steps = 400;
                        let dt = 0.5 / rate / f64::from(steps);
                        let de = rate * dt;
                        let mut state = MaterialState::initial(temperature);
                        for _ in 0..steps {
                            let before = state;
                            let input = StepInput {
                                strain_increment: [de, -0.5 * de, -0.5 * de, 0.0, 0.0, 0.0],
                                dt,
                                relative_volume: 1.0,
                            };
                            let output = update(&material, &mut state, &input).unwrap();
                            if output.plastic_increment > 0.0 {
                                let table = read.interpolate(
                                    reading,
                                    state.plastic_strain,
                                    output.plastic_increment / dt,
                                    before.temperature,
                                );
                                let relative =
                                    (table - output.yield_stress).abs() / output.yield_stress;
                                worst = worst.max(relative);
                            }
                        }
                    }
                }
                assert!(
                    worst <= 1.5 * error.relative,
                    "{name}, {reading:?}: history error {worst:e} against stated {:e}",
                    error.relative
                );
            }
        }
    }

    #[test]
    fn tabulated_cards_in_every_unit_system_read_back_to_the_si_table() {
        // GOAL: a *MAT_224 or Abaqus table written in a user's unit system holds the same
        //       material: read back as the code reads it and converted to SI, it is the SI
        //       table, stresses and rate abscissae alike.
        // SETUP: the JC family of the test set, cards in SI, mm-ms-kg-GPa, mm-s-t-MPa,
        //        mm-ms-g-MPa and cm-us-g-Mbar.
        // REFERENCE: the SI table the writer sampled; LS-DYNA's 20-column fields keep 15
        //            digits, Abaqus' numbers are exact, so within 1e-13 relative (ln rates
        //            within 1e-12 absolute).
        let (_, file) = families().into_iter().next().unwrap();
        for (name, options) in super::super::units::test_systems() {
            let units = &options.units;
            let (dyna, written, _) = ls_dyna(&file, &options).unwrap();
            let (inp, _, _) = abaqus(&file, &options).unwrap();
            assert!(
                dyna.contains(&units.header()) && inp.contains("NAME=HHA"),
                "{name}"
            );
            for read in [
                FlowTable::read_ls_dyna(&dyna).unwrap(),
                FlowTable::read_abaqus(&inp).unwrap(),
            ] {
                let si = read.to_si(units);
                for (a, b) in si.ln_rates.iter().zip(&written.ln_rates) {
                    assert!((a - b).abs() < 1e-12, "{name}: ln rate {a} against {b}");
                }
                for (t, rates) in si.values.iter().enumerate() {
                    for (r, values) in rates.iter().enumerate() {
                        for (e, value) in values.iter().enumerate() {
                            let exact = written.values[t][r][e];
                            assert!(
                                (value - exact).abs() <= 1e-13 * exact.abs().max(1.0),
                                "{name}: {value} against {exact}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn the_abaqus_card_asks_for_logarithmic_rate_interpolation_and_heats_adiabatically() {
        // GOAL: the Abaqus card is read the way its stated error assumes.
        // SETUP: the bundled 4340 Johnson-Cook file (adiabatic, Taylor-Quinney 0.9).
        // REFERENCE: Abaqus keywords reference: *MATERIAL's STRAIN RATE INTERPOLATION,
        //            *PLASTIC's RATE parameter, *INELASTIC HEAT FRACTION; one table per rate,
        //            in increasing rate order.
        let (_, file) = families().remove(0);
        let (card, table, _) = abaqus(&file, &CardOptions::default()).unwrap();
        assert!(card.contains("*MATERIAL, NAME=STOSS, STRAIN RATE INTERPOLATION=LOGARITHMIC\n"));
        assert!(card.contains("*INELASTIC HEAT FRACTION\n"));
        let rates: Vec<f64> = card
            .lines()
            .filter_map(|l| l.strip_prefix("*PLASTIC, RATE="))
            .map(|r| r.parse().unwrap())
            .collect();
        assert_eq!(rates.len(), table.ln_rates.len());
        assert!(rates.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn interpolation_is_linear_in_strain_ln_rate_and_temperature_and_clamped_outside() {
        // GOAL: the reading the card assumes, checked on a table of a known function.
        // SETUP: values a + b e + c ln(rate) + d T on a 3 x 2 x 2 grid.
        // REFERENCE: exact inside (the function is trilinear) in either reading; the nearest
        //            end outside in rate and temperature; beyond the largest strain, the last
        //            segment extended (LS-DYNA) or the last value held (Abaqus).
        let f = |e: f64, ln: f64, t: f64| 1.0 + 2.0 * e + 3.0 * ln + 0.01 * t;
        let plastic_strains = vec![0.0, 0.1, 1.0];
        let ln_rates = vec![-2.0, 3.0];
        let temperatures = vec![300.0, 900.0];
        let values = temperatures
            .iter()
            .map(|&t| {
                ln_rates
                    .iter()
                    .map(|&ln| plastic_strains.iter().map(|&e| f(e, ln, t)).collect())
                    .collect()
            })
            .collect();
        let table = FlowTable {
            plastic_strains,
            ln_rates,
            temperatures,
            values,
        };
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12 * b.abs().max(1.0);
        assert!(close(
            table.interpolate(Reading::LsDyna, 0.05, 1.0, 500.0),
            f(0.05, 0.0, 500.0)
        ));
        assert!(close(
            table.interpolate(Reading::LsDyna, 0.5, 10.0, 850.0),
            f(0.5, 10f64.ln(), 850.0)
        ));
        assert!(close(
            table.interpolate(Reading::LsDyna, 0.5, 1e-9, 850.0),
            f(0.5, -2.0, 850.0)
        ));
        assert!(close(
            table.interpolate(Reading::LsDyna, 0.5, 1.0, 2000.0),
            f(0.5, 0.0, 900.0)
        ));
        assert!(close(
            table.interpolate(Reading::LsDyna, 2.0, 1.0, 300.0),
            f(2.0, 0.0, 300.0)
        ));
        assert!(close(
            table.interpolate(Reading::AbaqusExplicit, 2.0, 1.0, 300.0),
            f(1.0, 0.0, 300.0)
        ));
        assert!(close(
            table.interpolate(Reading::AbaqusExplicit, 0.5, 10.0, 850.0),
            f(0.5, 10f64.ln(), 850.0)
        ));
    }
}
