//! RHT concrete model (seed 001 chapter 4) through the single-element drivers: the
//! single-element tests of seed 001 section 4.3.2 (hydrostatic loading and unloading,
//! uniaxial compression at several rates, uniaxial strain, uniaxial tension), checked
//! against the model's equations evaluated directly, plus parameter validation.
//!
//! Unless stated, the material is `RhtMaterial::HPC_92MPA`: seed table 4.4 over the
//! illustrative P-alpha EoS documented on that constant.

use stoss_kernel::drivers::{
    hydrostatic, strain_path, uniaxial_strain, uniaxial_stress, DriverError, HistorySink,
    HydrostaticLoading, PathPoint, Record, UniaxialStrainLoading, UniaxialStressLoading,
};
use stoss_kernel::eos::Eos;
use stoss_kernel::rht::{
    lode_factor_from_cos, strain_rate, update, FailureMeridian, Lode, RateScaling, RhtMaterial,
    RhtParameters, TensileFailure,
};
use stoss_kernel::tensor;
use stoss_kernel::{MaterialState, ParameterError, StateFlags, StepInput, UpdateError};

/// Unbounded record sink for tests.
#[derive(Default)]
struct History(Vec<Record>);

impl HistorySink for History {
    fn push(&mut self, record: Record) -> Result<(), DriverError> {
        self.0.push(record);
        Ok(())
    }
}

const FC: f64 = 92.0e6;

fn plastic(record: &Record) -> bool {
    record.flags & StateFlags::PLASTIC != 0
}

/// Uniaxial stress at `rate` (1/s) in direction `sign` (-1 compression, +1 tension) from
/// `state`, `steps` equal steps of `step` strain each.
fn uniaxial(
    material: &RhtMaterial,
    state: &mut MaterialState,
    rate: f64,
    sign: f64,
    step: f64,
    steps: u32,
) -> Vec<Record> {
    let mut history = History::default();
    uniaxial_stress(
        material,
        state,
        &UniaxialStressLoading {
            strain_rate: rate,
            final_strain: sign * step * f64::from(steps),
            steps,
        },
        &mut history,
    )
    .expect("uniaxial stress driver");
    history.0
}

/// Peak |axial stress| of uniaxial loading at `rate`: coarse steps of `coarse` strain to
/// locate the peak, then a rerun to two coarse steps before it and 2000 fine steps (1/1000
/// of a coarse step) over the four coarse steps around it. Coarse steps must be >= 2e-6: below that the first steps'
/// stresses are so small that the EoS pressure granularity (`K` times the spacing of doubles
/// near `V = 1`, ~2.4e-6 Pa) exceeds the driver's lateral tolerance. Returns the peak
/// record and the record before it (for the strain rate seen by the model).
fn uniaxial_peak(material: &RhtMaterial, rate: f64, sign: f64, coarse: f64) -> (Record, Record) {
    let limit = (0.008 / coarse) as u32;
    let mut state = material.initial_state(293.0);
    let records = uniaxial(material, &mut state, rate, sign, coarse, limit);
    let index = (0..records.len())
        .max_by(|&a, &b| {
            (sign * records[a].stress[0])
                .partial_cmp(&(sign * records[b].stress[0]))
                .unwrap()
        })
        .unwrap();
    assert!(index > 3 && index + 3 < records.len(), "peak not bracketed");
    let mut state = material.initial_state(293.0);
    uniaxial(material, &mut state, rate, sign, coarse, index as u32 - 1);
    let fine = uniaxial(material, &mut state, rate, sign, coarse / 1000.0, 4000);
    let peak = (0..fine.len())
        .max_by(|&a, &b| {
            (sign * fine[a].stress[0])
                .partial_cmp(&(sign * fine[b].stress[0]))
                .unwrap()
        })
        .unwrap();
    assert!(peak > 0 && peak + 1 < fine.len(), "fine peak not bracketed");
    (fine[peak], fine[peak - 1])
}

/// The model's strain rate (largest absolute principal strain rate) of the step ending at
/// `record`.
fn effective_rate(before: &Record, record: &Record) -> f64 {
    let increment: [f64; 6] = core::array::from_fn(|i| record.strain[i] - before.strain[i]);
    strain_rate(&increment, record.time - before.time)
}

/// Root of `Y_fail(z fc/3, compressive meridian, F) = z fc` (uniaxial compressive strength
/// in units of fc) by bisection on [0.5, 3].
fn uniaxial_compressive_strength(params: &RhtParameters, rate_factor: f64) -> f64 {
    let f = |z: f64| {
        params.failure_strength(z * FC / 3.0, Lode::COMPRESSIVE_MERIDIAN, rate_factor) - z * FC
    };
    let (mut lo, mut hi) = (0.5, 3.0);
    assert!(f(lo) > 0.0 && f(hi) < 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn table_4_4_fixture_matches_the_constant() {
    // GOAL: the shipped material file fixtures/materials/hpc-92-rht.toml and the kernel constant
    //   RhtParameters::HPC_92MPA hold the same numbers (seed 001 table 4.4, SI).
    // SETUP: parse the `key = value` lines of the material file's [parameters] table
    //   (comments stripped).
    // REFERENCE: the constant; tolerance: exact (same decimal literals).
    let text = include_str!("../../fixtures/materials/hpc-92-rht.toml");
    assert!(text.contains("FOI-R--0281--SE (2001)") && text.contains("table 4.4"));
    let p = RhtParameters::HPC_92MPA;
    let numbers: [(&str, f64); 22] = [
        ("shear_modulus", p.shear_modulus),
        ("compressive_strength", p.compressive_strength),
        ("tensile_strength_ratio", p.tensile_strength_ratio),
        ("shear_strength_ratio", p.shear_strength_ratio),
        ("failure_a", p.failure_a),
        ("failure_n", p.failure_n),
        ("tensile_meridian_ratio", p.tensile_meridian_ratio),
        ("brittle_ductile_transition", p.brittle_ductile_transition),
        ("shear_modulus_ratio", p.shear_modulus_ratio),
        ("tensile_elastic_ratio", p.tensile_elastic_ratio),
        ("compressive_elastic_ratio", p.compressive_elastic_ratio),
        ("residual_b", p.residual_b),
        ("residual_m", p.residual_m),
        ("compressive_rate_exponent", p.compressive_rate_exponent),
        ("tensile_rate_exponent", p.tensile_rate_exponent),
        ("compressive_reference_rate", p.compressive_reference_rate),
        ("tensile_reference_rate", p.tensile_reference_rate),
        ("damage_d1", p.damage_d1),
        ("damage_d2", p.damage_d2),
        ("minimum_failure_strain", p.minimum_failure_strain),
        (
            "residual_shear_modulus_ratio",
            p.residual_shear_modulus_ratio,
        ),
        ("shear_modulus", p.shear_modulus),
    ];
    let mut fields = std::collections::BTreeMap::new();
    let mut section = "";
    for line in text.lines() {
        let line = line.split('#').next().unwrap().trim();
        if line.starts_with('[') {
            section = line;
            continue;
        }
        if section != "[parameters]" {
            continue;
        }
        if let Some((key, value)) = line.split_once('=') {
            fields.insert(key.trim().to_string(), value.trim().to_string());
        }
    }
    assert_eq!(fields.len(), 25, "fixture field count");
    for (key, value) in numbers {
        let parsed: f64 = fields[key].parse().unwrap();
        assert_eq!(parsed, value, "{key}");
    }
    assert_eq!(fields["elastic_cap"], "true");
    assert!(p.elastic_cap);
    assert_eq!(fields["tensile_failure"], "\"hydro-tensile-limit\"");
    assert_eq!(p.tensile_failure, TensileFailure::HydroTensileLimit);
    assert_eq!(fields["meridian"], "\"characteristic-points\"");
    assert_eq!(p.meridian, FailureMeridian::CharacteristicPoints);
    assert_eq!(fields["rate_scaling"], "\"seed-equation\"");
    assert_eq!(p.rate_scaling, RateScaling::SeedEquation);
    assert_eq!(RhtMaterial::HPC_92MPA.validate(), Ok(()));
}

#[test]
fn lode_factor_is_one_on_the_compressive_and_q2_on_the_tensile_meridian() {
    // GOAL: eq. 4.2 gives R3 = 1 on the compressive meridian (theta = pi/3) and R3 = Q2 on
    //   the tensile meridian (theta = 0), with Q2 = Q2,0 + BQ p* clamped to [0.5, 1]
    //   (eq. 4.3); the Lode angle of uniaxial compression / tension / pure shear deviators
    //   is pi/3 / 0 / pi/6.
    // SETUP: table 4.4 constants, p* from -30 (Q2 clamped at 0.5) to 40 (clamped at 1).
    // REFERENCE: the closed forms; tolerance 1e-15 absolute (R3), 1e-12 (cos theta).
    let p = RhtParameters::HPC_92MPA;
    for p_star in [-30.0, -0.05, 0.0, 1.0 / 3.0, 2.0, 10.0, 40.0] {
        let pressure = p_star * FC;
        let q2 = (0.6805 + 0.0105 * p_star).clamp(0.5, 1.0);
        assert_eq!(p.tensile_meridian_ratio_at(p_star), q2);
        let compressive = p.lode_factor(Lode::COMPRESSIVE_MERIDIAN, pressure);
        let tensile = p.lode_factor(Lode::TENSILE_MERIDIAN, pressure);
        assert!(
            (compressive - 1.0).abs() < 1e-15,
            "p* {p_star}: {compressive}"
        );
        assert!(
            (tensile - q2).abs() < 1e-15,
            "p* {p_star}: {tensile} vs {q2}"
        );
        // Through the angle, too.
        let from_angle = p.lode_factor(Lode::from_angle(core::f64::consts::FRAC_PI_3), pressure);
        assert!((from_angle - 1.0).abs() < 1e-15);
        // Monotonic between the meridians (Willam-Warnke is convex and smooth).
        let shear = p.lode_factor(Lode::SHEAR_MERIDIAN, pressure);
        assert!(shear > q2 && shear < 1.0 || q2 == 1.0);
    }
    assert_eq!(lode_factor_from_cos(0.5, 0.5), 1.0);
    assert_eq!(lode_factor_from_cos(1.0, 0.5), 0.5);
    let q = 1e8;
    let compression = tensor::deviator(&[-q, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let tension = tensor::deviator(&[q, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let shear = [0.0, 0.0, 0.0, 0.0, 0.0, q];
    // On a meridian two principal stresses coincide and the Lode angle is ill-conditioned:
    // an ulp in cos 3theta = -+1 moves cos theta by ~sqrt(ulp) ~ 1e-8. Tolerance 1e-7.
    assert!((Lode::from_deviator(&compression).cos_theta - 0.5).abs() < 1e-7);
    assert!((Lode::from_deviator(&tension).cos_theta - 1.0).abs() < 1e-7);
    assert!((Lode::from_deviator(&shear).cos_theta - libm::sqrt(3.0) / 2.0).abs() < 1e-12);
    // Triaxial extension (two equal tensions) is on the tensile meridian too... no:
    // sigma = (0, q, q) has deviator (-2, 1, 1) q/3, the compressive-meridian shape's
    // negative, i.e. J3 > 0: tensile meridian.
    let extension = tensor::deviator(&[0.0, -q, -q, 0.0, 0.0, 0.0]);
    assert!((Lode::from_deviator(&extension).cos_theta - 1.0).abs() < 1e-12);
}

#[test]
fn failure_meridian_passes_the_characteristic_points_and_eq_4_1() {
    // GOAL: the quasi-static failure surface passes through uniaxial compression (fc at
    //   p = fc/3, compressive meridian), uniaxial tension (ft at p = -ft/3, tensile
    //   meridian), pure shear (FS* fc at p = 0, shear meridian), vanishes at p*_spall, and
    //   above fc/3 is eq. 4.1 literally, fc F A (p* - p*_spall,0 F)^N R3, for the seed
    //   scaling at any F. The elastic surface meets the uniaxial paths at COMPRAT fc and
    //   TENSRAT ft and its cap closes it at the P-alpha crush pressure.
    // SETUP: table 4.4; F in {1, 1.1, 1.4}. REFERENCE: closed forms; tolerance 1e-12 rel.
    let p = RhtParameters::HPC_92MPA;
    let ft = p.tensile_strength();
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    assert!(
        rel(
            p.failure_strength(FC / 3.0, Lode::COMPRESSIVE_MERIDIAN, 1.0),
            FC
        ) < 1e-12
    );
    assert!(
        rel(
            p.failure_strength(-ft / 3.0, Lode::TENSILE_MERIDIAN, 1.0),
            ft
        ) < 1e-12
    );
    assert!(
        rel(
            p.failure_strength(0.0, Lode::SHEAR_MERIDIAN, 1.0),
            0.30 * FC
        ) < 1e-12
    );
    let spall = p.spall_pressure_ratio() * FC;
    assert_eq!(
        p.failure_strength(spall * (1.0 + 1e-9), Lode::COMPRESSIVE_MERIDIAN, 1.0),
        0.0
    );
    assert!(p.failure_strength(spall * (1.0 - 1e-6), Lode::COMPRESSIVE_MERIDIAN, 1.0) > 0.0);
    // Elastic surface: the failure surface scaled about the origin, so the elastic limits on
    // the uniaxial paths are COMPRAT fc and TENSRAT ft; the cap closes it at p_crush.
    let material = RhtMaterial::HPC_92MPA;
    let cap = material.cap_pressure();
    let crush = cap.unwrap();
    let compression = p.elastic_strength(0.75 * FC / 3.0, Lode::COMPRESSIVE_MERIDIAN, 1.0, cap);
    assert!(rel(compression, 0.75 * FC) < 1e-12, "{compression}");
    let tension = p.elastic_strength(-0.8 * ft / 3.0, Lode::TENSILE_MERIDIAN, 1.0, cap);
    assert!(rel(tension, 0.8 * ft) < 1e-12, "{tension}");
    assert_eq!(p.cap_factor(0.75 * FC / 3.0, cap), 1.0);
    assert!(p.cap_factor(0.5 * (0.75 * FC / 3.0 + crush), cap) < 1.0);
    assert_eq!(
        p.elastic_strength(crush, Lode::COMPRESSIVE_MERIDIAN, 1.0, cap),
        0.0
    );
    assert!(p.elastic_strength(crush, Lode::COMPRESSIVE_MERIDIAN, 1.0, None) > 0.0);
    let p0 = p.power_law_intercept();
    assert!(rel(p0, 1.0 / 3.0 - libm::pow(1.9, -1.0 / 0.6)) < 1e-15);
    for f in [1.0, 1.1, 1.4] {
        for p_star in [0.5, 1.0, 3.0, 10.0] {
            let pressure = p_star * FC * f;
            let lode = Lode::from_angle(0.4);
            let eq_4_1 = FC
                * f
                * 1.9
                * libm::pow(pressure / FC - p0 * f, 0.6)
                * p.lode_factor(lode, pressure);
            assert!(
                rel(p.failure_strength(pressure, lode, f), eq_4_1) < 1e-12,
                "F {f}"
            );
        }
    }
    std::println!(
        "p*_spall {:.5} (p_spall {:.3} MPa), power-law intercept {:.5}",
        p.spall_pressure_ratio(),
        spall / 1e6,
        p0
    );
}

#[test]
fn rate_factor_has_two_branches_and_a_linear_transition() {
    // GOAL: eq. 4.4: (rate/30e-6)^alpha for p >= fc/3, (rate/3e-6)^delta for p <= -ft/3,
    //   linear in p between, 1 below the reference rates.
    // SETUP: table 4.4 (alpha 0.010, delta 0.013), rate 100 /s.
    // REFERENCE: the formulas; tolerance 1e-15 relative.
    let p = RhtParameters::HPC_92MPA;
    let ft = p.tensile_strength();
    let fc_branch = libm::pow(100.0 / 30e-6, 0.010);
    let ft_branch = libm::pow(100.0 / 3e-6, 0.013);
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    assert!(rel(p.rate_factor(100.0, FC / 3.0), fc_branch) < 1e-15);
    assert!(rel(p.rate_factor(100.0, 5.0 * FC), fc_branch) < 1e-15);
    assert!(rel(p.rate_factor(100.0, -ft / 3.0), ft_branch) < 1e-15);
    assert!(rel(p.rate_factor(100.0, -10.0 * ft), ft_branch) < 1e-15);
    let middle = 0.5 * (FC / 3.0 - ft / 3.0);
    assert!(rel(p.rate_factor(100.0, middle), 0.5 * (fc_branch + ft_branch)) < 1e-14);
    assert_eq!(p.rate_factor(1e-6, FC), 1.0);
    assert_eq!(p.rate_factor(2e-6, -FC), 1.0);
    assert_eq!(p.rate_factor(0.0, 0.0), 1.0);
}

#[test]
fn hydrostatic_loading_and_unloading_follows_the_p_alpha_curve() {
    // GOAL: under hydrostatic loading and unloading the pressure is the P-alpha EoS (seed
    //   eqs. 4.10-4.11, fig. 4.11) evaluated directly: no deviatoric stress, elastic to the
    //   crush pressure, compaction (alpha decreasing) beyond, elastic unloading at constant
    //   alpha with permanent densification; on unloading into tension the hydro tensile
    //   limit fails the point (D = 1), after which the pressure is held at 0.
    // SETUP: HPC_92MPA, hydrostatic driver, volumetric compression 0.06 in 3000 steps at
    //   10 /s, unloaded to V0 in 3000 steps.
    // REFERENCE: PAlpha::evaluate along the recorded path (mu from V = exp(tr eps), alpha
    //   carried, recorded energy); energy by the trapezoidal rule E1 = E0 - (p0+p1)/2 dV.
    //   Tolerances: pressure 1e-9 relative + 0.1 Pa (the test rebuilds V from the summed log
    //   strain, the driver multiplies per step: ~1e-13 apart after 6000 steps, times K),
    //   energy 1e-9 relative + 1e-3 J/m^3.
    let material = RhtMaterial::HPC_92MPA;
    let Eos::PAlpha(eos) = material.eos else {
        panic!("P-alpha expected")
    };
    let mut state = material.initial_state(293.0);
    let mut history = History::default();
    hydrostatic(
        &material,
        &mut state,
        &HydrostaticLoading {
            peak_compression: 0.06,
            strain_rate: 10.0,
            loading_steps: 3000,
            unloading_steps: 3000,
        },
        &mut history,
    )
    .unwrap();
    let records = history.0;
    let mut alpha = eos.initial_distension;
    let (mut previous_p, mut previous_v, mut previous_e) = (0.0, 1.0, 0.0);
    let mut failed_at = None;
    let mut crush_seen = false;
    let mut peak = (0.0, 0.0, 0.0); // (pressure, mu, alpha) at peak compression
    for (k, record) in records.iter().enumerate() {
        // Equal normal strains: the deviator is zero up to the rounding of tr/3.
        assert!(record.equivalent_stress < 1e-6, "deviator at step {k}");
        let volume = libm::exp(tensor::trace(&record.strain));
        let mu = 1.0 / volume - 1.0;
        let (terms, next_alpha) = eos.evaluate(mu, alpha);
        assert!(next_alpha <= alpha, "alpha increased at step {k}");
        alpha = next_alpha;
        let expected = terms.pressure(record.internal_energy);
        if record.flags & StateFlags::PRESSURE_CUTOFF != 0 || failed_at.is_some() {
            assert!(expected <= record.pressure + 1e-3);
        } else {
            assert!(
                (record.pressure - expected).abs() <= 1e-9 * expected.abs() + 0.1,
                "step {k}: {} vs {expected}",
                record.pressure
            );
        }
        let energy = previous_e - 0.5 * (previous_p + record.pressure) * (volume - previous_v);
        assert!((record.internal_energy - energy).abs() <= 1e-9 * energy.abs() + 1e-3);
        if record.flags & StateFlags::FAILED != 0 && failed_at.is_none() {
            failed_at = Some(k);
            assert_eq!(record.damage, 1.0);
            assert!(k > 3000, "failed while loading");
        }
        if failed_at.is_some() {
            assert!(record.pressure >= 0.0);
            assert_eq!(record.flags & StateFlags::ERODE, 0);
        }
        if alpha < eos.initial_distension && !crush_seen {
            crush_seen = true;
            // Elastic up to the crush pressure (first compaction step within one step).
            assert!(
                record.pressure > eos.crush_pressure * 0.99,
                "{}",
                record.pressure
            );
            assert!(records[k - 1].pressure <= eos.crush_pressure * (1.0 + 1e-12));
        }
        if k == 2999 {
            peak = (record.pressure, mu, alpha);
        }
        (previous_p, previous_v, previous_e) = (record.pressure, volume, record.internal_energy);
    }
    assert!(crush_seen, "no compaction");
    let failed_at = failed_at.expect("unloading into tension should fail at the hydro limit");
    // Elastic start: dp/dmu = A1/alpha0 = 21.5 GPa (seed section 4.3.1 bulk modulus).
    let volume = libm::exp(tensor::trace(&records[9].strain));
    let slope = records[9].pressure / (1.0 / volume - 1.0);
    assert!(
        (slope / 21.47e9 - 1.0).abs() < 2e-3,
        "elastic bulk modulus {slope}"
    );
    // Unloading at constant alpha is stiffer than loading; permanent densification.
    let (peak_p, peak_mu, peak_alpha) = peak;
    let loading_slope = (peak_p - records[2899].pressure)
        / (peak_mu - (1.0 / libm::exp(tensor::trace(&records[2899].strain)) - 1.0));
    let unloading_slope = (peak_p - records[3100].pressure)
        / (peak_mu - (1.0 / libm::exp(tensor::trace(&records[3100].strain)) - 1.0));
    assert!(unloading_slope > 1.5 * loading_slope);
    let residual_density = eos.initial_distension / peak_alpha;
    assert!(residual_density > 1.02);
    // The hydro tensile limit of the table 4.4 surface.
    let limit = material.parameters.spall_pressure_ratio() * FC;
    assert!(records[failed_at - 1].pressure >= limit);
    std::println!(
        "peak p {:.1} MPa at mu {:.4}, alpha {:.4} (alpha0 {:.4}); loading dp/dmu {:.1} GPa, \
         unloading {:.1} GPa; residual rho/rho0 {:.4}; failed in tension at step {failed_at} \
         (hydro limit {:.2} MPa)",
        peak_p / 1e6,
        peak_mu,
        peak_alpha,
        eos.initial_distension,
        loading_slope / 1e9,
        unloading_slope / 1e9,
        residual_density,
        limit / 1e6
    );
}

#[test]
fn quasi_static_uniaxial_compression_peaks_at_fc() {
    // GOAL: at a quasi-static rate (below both reference rates, F_rate = 1) the peak
    //   uniaxial compressive stress is fc = 92 MPa; the elastic limit is COMPRAT fc = 69 MPa.
    // SETUP: HPC_92MPA, uniaxial stress driver at 1e-6 /s (below the 3e-6 /s tensile
    //   reference too, which matters below p = fc/3 where the rate factor interpolates
    //   between the branches), coarse steps 2e-6 then 2e-9 across the peak.
    // REFERENCE: fc (the surface is anchored there, seed table 4.4). Tolerances: the brief's
    //   1 %; the implementation reaches 1e-5, asserted at 1e-4. Elastic limit: bracketed by
    //   the last elastic and first plastic coarse records.
    let material = RhtMaterial::HPC_92MPA;
    let (peak, _) = uniaxial_peak(&material, 1e-6, -1.0, 2e-6);
    let measured = -peak.stress[0];
    std::println!(
        "quasi-static peak {:.5} MPa (fc 92), pressure {:.4} MPa, strain {:.6}",
        measured / 1e6,
        peak.pressure / 1e6,
        peak.strain[0]
    );
    assert!((measured / FC - 1.0).abs() < 1e-4, "peak {measured}");
    assert!((measured / FC - 1.0).abs() < 1e-2);
    let mut state = material.initial_state(293.0);
    let records = uniaxial(&material, &mut state, 1e-6, -1.0, 2e-6, 1200);
    let first = records.iter().position(plastic).unwrap();
    let elastic_limit = 0.75 * FC;
    assert!(-records[first - 1].stress[0] <= elastic_limit);
    assert!(-records[first].stress[0] >= elastic_limit * (1.0 - 1e-12));
    assert!(-records[first].stress[0] - elastic_limit < 50e3);
}

#[test]
fn uniaxial_compression_dynamic_increase_follows_the_rate_factor() {
    // GOAL: the dynamic increase factor DIF = peak(rate)/fc of uniaxial compression.
    //   Seed fig. 4.12 ("DIF for uni-axial compressive stress with pressure effects
    //   included", alpha 0.01 for HPC) describes DIF against (rate/rate0)^alpha.
    //   (a) RateScaling::SeedEquation (eqs. 4.1, 4.5 as printed, the table 4.4 constant):
    //       the DIF equals the root of Y_fail(z fc/3, F) = z fc, about F^(1/(1-N)) -- larger
    //       than F = (rate/rate0)^alpha because of the pressure effect;
    //   (b) RateScaling::Homothetic: DIF = F = (rate/rate0)^alpha.
    // SETUP: HPC_92MPA (and its homothetic variant), uniaxial stress at 1e-5, 1, 10, 100,
    //   1000 /s; coarse steps 2e-6 refined 1000x across the peak. F is evaluated with the
    //   model's effective (deviatoric) strain rate of the peak step; at the peak the flow
    //   is plastic and incompressible, so it equals the axial rate (checked, 1e-3).
    // REFERENCE: (a) the surface equation solved by bisection, tolerance 1e-4 relative;
    //   (b) F, tolerance 1e-4 relative.
    let seed = RhtMaterial::HPC_92MPA;
    let mut homothetic = seed;
    homothetic.parameters.rate_scaling = RateScaling::Homothetic;
    let params = seed.parameters;
    for rate in [1e-6, 1.0, 10.0, 100.0, 1000.0] {
        let formula = if rate > 30e-6 {
            libm::pow(rate / 30e-6, 0.010)
        } else {
            1.0
        };
        let (peak, before) = uniaxial_peak(&seed, rate, -1.0, 2e-6);
        let seen = effective_rate(&before, &peak);
        assert!(
            (seen / rate - 1.0).abs() < 1e-9,
            "rate {rate}: model saw {seen}"
        );
        let factor = params.rate_factors(seen).0;
        let expected = uniaxial_compressive_strength(&params, factor);
        let dif = -peak.stress[0] / FC;
        let (peak_h, before_h) = uniaxial_peak(&homothetic, rate, -1.0, 2e-6);
        let factor_h = params.rate_factors(effective_rate(&before_h, &peak_h)).0;
        let dif_h = -peak_h.stress[0] / FC;
        std::println!(
            "rate {rate:>7} /s: (rate/rate0)^alpha = {formula:.4}; seed-equation DIF {dif:.4} \
             (surface root {expected:.4}, F^(1/(1-N)) {:.4}); homothetic DIF {dif_h:.4} \
             (F {factor_h:.4}); model rate {:.4} x axial",
            libm::pow(formula, 1.0 / 0.4),
            seen / rate
        );
        assert!((dif / expected - 1.0).abs() < 1e-4, "seed DIF at {rate}");
        assert!(
            (dif_h / factor_h - 1.0).abs() < 1e-4,
            "homothetic DIF at {rate}"
        );
        assert!((factor / formula - 1.0).abs() < 1e-9);
        assert!(
            dif >= dif_h * (1.0 - 1e-4),
            "pressure effect should raise the DIF"
        );
    }
}

#[test]
fn uniaxial_strain_stress_difference_follows_the_surfaces() {
    // GOAL: uniaxial strain compression (seed figs. 4.14, 4.15, without rate enhancement,
    //   alpha = 0): at every plastic step the stress difference |sigma_axial - sigma_radial|
    //   = sigma_eq equals the current strength evaluated directly from the surface equations
    //   at the recorded pressure, plastic strain and damage (hardening from the capped
    //   elastic surface, then damage softening towards the residual surface), and the axial
    //   stress is -p - 2/3 sigma_eq; elastic steps stay inside.
    // SETUP: HPC_92MPA with alpha = delta = 0, uniaxial strain driver to -5 % in 5000 steps
    //   at 1 /s.
    // REFERENCE: RhtParameters::surfaces(p, compressive meridian, F = 1, cap).current(eps_p,
    //   D). Tolerance 2e-5 fc: the return is made at the pressure predictor, the recorded
    //   pressure also holds the energy term of the step's deviatoric work.
    let mut material = RhtMaterial::HPC_92MPA;
    material.parameters.compressive_rate_exponent = 0.0;
    material.parameters.tensile_rate_exponent = 0.0;
    let params = material.parameters;
    let mut state = material.initial_state(293.0);
    let mut history = History::default();
    uniaxial_strain(
        &material,
        &mut state,
        &UniaxialStrainLoading {
            strain_rate: 1.0,
            final_strain: -0.05,
            steps: 5000,
        },
        &mut history,
    )
    .unwrap();
    let records = history.0;
    let mut worst: f64 = 0.0;
    let mut plastic_steps = 0;
    for record in &records {
        let difference = record.stress[1] - record.stress[0];
        assert!((difference - record.equivalent_stress).abs() <= 1e-9 * FC);
        let lode = Lode::from_deviator(&tensor::deviator(&record.stress));
        assert!(
            (lode.cos_theta - 0.5).abs() < 1e-6,
            "not on the compressive meridian"
        );
        let surfaces = params.surfaces(
            record.pressure,
            Lode::COMPRESSIVE_MERIDIAN,
            1.0,
            material.cap_pressure(),
        );
        let strength = surfaces.current(record.plastic_strain, record.damage);
        if plastic(record) {
            plastic_steps += 1;
            worst = worst.max((record.equivalent_stress - strength).abs() / FC);
            let axial = -record.pressure - 2.0 / 3.0 * strength;
            assert!((record.stress[0] - axial).abs() <= 2e-5 * FC);
        } else {
            assert!(record.equivalent_stress <= strength + 2e-5 * FC);
        }
    }
    assert!(plastic_steps > 4000);
    assert!(worst < 2e-5, "worst {worst}");
    let at = |k: usize| &records[k];
    for k in [199, 499, 999, 1999, 2999, 4999] {
        let r = at(k);
        std::println!(
            "eps {:.4}: p {:7.1} MPa, sigma_axial {:7.1} MPa, difference {:6.1} MPa, \
             eps_p {:.4}, D {:.3}",
            r.strain[0],
            r.pressure / 1e6,
            r.stress[0] / 1e6,
            r.equivalent_stress / 1e6,
            r.plastic_strain,
            r.damage
        );
    }
    std::println!("worst |sigma_eq - Y| / fc over plastic steps: {worst:.2e}");
    // Confinement: the stress difference far exceeds fc at high pressure.
    assert!(records[999].equivalent_stress > FC);
}

#[test]
fn uniaxial_tension_peaks_at_ft() {
    // GOAL: quasi-static uniaxial tension peaks at ft = FT* fc (seed section 4.3.1: 5.2 MPa;
    //   0.057 x 92 MPa = 5.244 MPa); the elastic limit is TENSRAT ft; after the peak the
    //   stress softens with damage (D > 0).
    // SETUP: HPC_92MPA, uniaxial stress at 1e-6 /s (below the 3e-6 /s reference, F = 1),
    //   coarse steps 2e-6, refined 1000x across the peak.
    // REFERENCE: FT* fc, tolerance 1e-4 relative; the seed's rounded 5.2 MPa within 1 %.
    let material = RhtMaterial::HPC_92MPA;
    let ft = material.parameters.tensile_strength();
    let (peak, _) = uniaxial_peak(&material, 1e-6, 1.0, 2e-6);
    std::println!(
        "tension peak {:.5} MPa (FT* fc = {:.4} MPa, seed 5.2 MPa), pressure {:.4} MPa, \
         strain {:.3e}",
        peak.stress[0] / 1e6,
        ft / 1e6,
        peak.pressure / 1e6,
        peak.strain[0]
    );
    assert!((peak.stress[0] / ft - 1.0).abs() < 1e-4);
    assert!((peak.stress[0] / 5.2e6 - 1.0).abs() < 1e-2);
    let mut state = material.initial_state(293.0);
    let records = uniaxial(&material, &mut state, 1e-6, 1.0, 2e-6, 150);
    let first = records.iter().position(plastic).unwrap();
    let elastic_limit = 0.8 * ft;
    assert!(records[first - 1].stress[0] <= elastic_limit);
    assert!(records[first].stress[0] >= elastic_limit * (1.0 - 1e-12));
    let last = records.last().unwrap();
    assert!(
        last.damage > 0.0 && last.stress[0] < 0.999 * ft,
        "no softening"
    );
}

#[test]
fn damage_leaves_residual_strength_and_erodes_only_by_strain() {
    // GOAL: past the failure surface D = sum(d eps_p / eps_f) grows (eqs. 4.6-4.7) until
    //   D = 1; then the point keeps the residual strength of eq. 4.8 (FAILED set, ERODE not:
    //   RHT does not delete). ERODE is set only by the erosion strain.
    // SETUP: HPC_92MPA quasi-static uniaxial compression to -2 % (coarse steps 2e-6); again
    //   with erosion_plastic_strain 0.01.
    // REFERENCE: on the uniaxial path sigma = 3p, so the residual strength solves
    //   fc B p*^M = 3 p* fc: p* = (B/3)^(1/(1-M)), sigma = 3 p* fc (25.3 MPa); tolerance
    //   1e-4 relative. The damage increments match d eps_p / eps_f(p) (1e-9).
    let material = RhtMaterial::HPC_92MPA;
    let params = material.parameters;
    let mut state = material.initial_state(293.0);
    let records = uniaxial(&material, &mut state, 1e-5, -1.0, 2e-6, 10_000);
    let failed = records
        .iter()
        .position(|r| r.flags & StateFlags::FAILED != 0)
        .expect("D should reach 1");
    for pair in records[..failed].windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if a.damage > 0.0 {
            let expected =
                (b.plastic_strain - a.plastic_strain) / params.failure_strain(b.pressure);
            assert!((b.damage - a.damage - expected).abs() < 1e-6 * expected + 1e-9);
        }
    }
    let last = records.last().unwrap();
    assert_eq!(last.damage, 1.0);
    assert_eq!(last.flags & StateFlags::ERODE, 0);
    let p_star = libm::pow(1.3 / 3.0, 1.0 / 0.35);
    let residual = 3.0 * p_star * FC;
    std::println!(
        "D = 1 at axial strain {:.4}; residual uniaxial strength {:.3} MPa (closed form \
         {:.3} MPa)",
        records[failed].strain[0],
        -last.stress[0] / 1e6,
        residual / 1e6
    );
    assert!((-last.stress[0] / residual - 1.0).abs() < 1e-4);
    let mut eroding = material;
    eroding.erosion_plastic_strain = Some(0.01);
    let mut state = eroding.initial_state(293.0);
    let records = uniaxial(&eroding, &mut state, 1e-5, -1.0, 2e-6, 10_000);
    let erode = records
        .iter()
        .position(|r| r.flags & StateFlags::ERODE != 0)
        .expect("erosion");
    assert!(records[erode].plastic_strain >= 0.01);
    assert!(records[erode - 1].plastic_strain < 0.01);
}

/// Equal triaxial expansion to `final_strain` (log strain per axis) over 1e4 s in `steps`
/// steps along the strain-path driver.
fn triaxial_tension(material: &RhtMaterial, final_strain: f64, steps: u32) -> Vec<Record> {
    let mut state = material.initial_state(293.0);
    let mut history = History::default();
    let path = [
        PathPoint {
            time: 0.0,
            strain: [0.0; 6],
            temperature: None,
        },
        PathPoint {
            time: 1.0e4,
            strain: [final_strain, final_strain, final_strain, 0.0, 0.0, 0.0],
            temperature: None,
        },
    ];
    strain_path(material, &mut state, &path, steps, &mut history).unwrap();
    history.0
}

#[test]
fn hydrostatic_tension_fails_at_the_hydro_limit_or_at_ft() {
    // GOAL: the two tensile failure options (seed section 4.3.1): "Hydro tensile limit"
    //   fails the point when the pressure would fall below p*_spall fc (where the failure
    //   surface meets the pressure axis); "Principal stress" when the largest principal
    //   stress reaches ft. After failure the pressure is held at 0 (no tension).
    // SETUP: HPC_92MPA (hydro) and its principal-stress variant, equal triaxial extension
    //   to 5e-4 per axis in 5000 steps over 1e4 s (5e-8 /s, below the references: F = 1;
    //   at 5e-4 /s the tensile rate factor 1.069 would move both limits by 6.9 %).
    // REFERENCE: hydro: last pressure before failure >= p*_spall fc (-2.22 MPa) and the
    //   EoS step past it; principal: -p reaches ft = 5.244 MPa within one step (2.2 %).
    let hydro = RhtMaterial::HPC_92MPA;
    let mut principal = hydro;
    principal.parameters.tensile_failure = TensileFailure::PrincipalStress;
    for (material, limit) in [
        (hydro, hydro.parameters.spall_pressure_ratio() * FC),
        (principal, -hydro.parameters.tensile_strength()),
    ] {
        let records = triaxial_tension(&material, 5e-4, 5000);
        let failed = records
            .iter()
            .position(|r| r.flags & StateFlags::FAILED != 0)
            .expect("no tensile failure");
        let before = records[failed - 1].pressure;
        // Pressure change of one step before failure: the EoS pressure of the failing step
        // is below the limit, so the limit lies within one such step of `before`.
        let step = (records[failed - 1].pressure - records[failed - 2].pressure).abs();
        std::println!(
            "{:?}: last pressure before failure {:.4} MPa (limit {:.4} MPa)",
            material.parameters.tensile_failure,
            before / 1e6,
            limit / 1e6
        );
        assert!(before >= limit);
        assert!(
            before - limit <= step * 1.01,
            "{before} vs {limit}, step {step}"
        );
        for r in &records[failed..] {
            assert!(r.pressure >= 0.0);
            assert_eq!(r.damage, 1.0);
            assert_eq!(r.flags & StateFlags::ERODE, 0);
        }
    }
}

#[test]
fn the_pressure_cutoff_holds_hydrostatic_tension_at_the_limit_without_failing() {
    // GOAL: the LS-DYNA *MAT_RHT tensile option: the pressure is held at the hydrostatic
    //   tensile limit p*_spall fc (1 - D) and the point does not fail; under equal triaxial
    //   extension there is no deviatoric stress, hence no plastic strain and no damage.
    // SETUP: HPC_92MPA with tensile_failure = PressureCutoff, the extension of the test above
    //   (5e-4 per axis, 5000 steps over 1e4 s, F = 1).
    // REFERENCE: once below the limit, every step's pressure equals it exactly (-2.22 MPa)
    //   with the PRESSURE_CUTOFF flag; D stays 0, nothing fails or erodes; the pressure rises
    //   past the limit only through it (no step below).
    let mut material = RhtMaterial::HPC_92MPA;
    material.parameters.tensile_failure = TensileFailure::PressureCutoff;
    let limit = material.parameters.spall_pressure_ratio() * FC;
    let records = triaxial_tension(&material, 5e-4, 5000);
    let held = records
        .iter()
        .position(|r| r.flags & StateFlags::PRESSURE_CUTOFF != 0)
        .expect("never held");
    assert!(held > 10 && held < records.len() - 10);
    for r in &records {
        assert!(r.pressure >= limit, "{} below {limit}", r.pressure);
        assert_eq!(r.damage, 0.0);
        assert_eq!(r.flags & (StateFlags::FAILED | StateFlags::ERODE), 0);
    }
    for r in &records[held..] {
        assert_eq!(r.pressure, limit);
    }
}

#[test]
fn bad_parameters_give_typed_errors() {
    // GOAL: validate() names the offending field with a typed error, through RhtMaterial
    //   and through the drivers; an update with bad input leaves the state unchanged.
    // SETUP: table 4.4 with one field broken at a time.
    // REFERENCE: the ParameterError / UpdateError variants.
    let good = RhtMaterial::HPC_92MPA;
    let broken = |edit: &dyn Fn(&mut RhtMaterial)| {
        let mut m = good;
        edit(&mut m);
        m.validate()
    };
    assert_eq!(
        broken(&|m| m.parameters.compressive_strength = 0.0),
        Err(ParameterError::NotPositive {
            field: "compressive_strength",
            value: 0.0
        })
    );
    assert_eq!(
        broken(&|m| m.parameters.failure_a = f64::NAN),
        Err(ParameterError::NotFinite { field: "failure_a" })
    );
    assert!(matches!(
        broken(&|m| m.parameters.tensile_meridian_ratio = 0.4),
        Err(ParameterError::OutOfRange {
            field: "tensile_meridian_ratio",
            ..
        })
    ));
    assert!(matches!(
        broken(&|m| m.parameters.compressive_elastic_ratio = 1.2),
        Err(ParameterError::OutOfRange {
            field: "compressive_elastic_ratio",
            ..
        })
    ));
    assert!(matches!(
        broken(&|m| m.parameters.shear_modulus_ratio = 0.5),
        Err(ParameterError::OutOfRange {
            field: "shear_modulus_ratio",
            ..
        })
    ));
    assert_eq!(
        broken(&|m| m.parameters.damage_d1 = -0.04),
        Err(ParameterError::NotPositive {
            field: "damage_d1",
            value: -0.04
        })
    );
    assert_eq!(
        broken(&|m| m.parameters.compressive_rate_exponent = -0.01),
        Err(ParameterError::Negative {
            field: "compressive_rate_exponent",
            value: -0.01
        })
    );
    // Shear point below the tension point: the meridian would fall.
    assert_eq!(
        broken(&|m| m.parameters.shear_strength_ratio = 0.03),
        Err(ParameterError::Inconsistent {
            field: "shear_strength_ratio",
            other: "tensile_strength_ratio"
        })
    );
    // Pure power law through (1/3, 1) with A >= 3^N has no strength at zero pressure.
    assert_eq!(
        broken(&|m| {
            m.parameters.meridian = FailureMeridian::PowerLaw;
            m.parameters.failure_a = 2.0;
        }),
        Err(ParameterError::Inconsistent {
            field: "failure_a",
            other: "failure_n"
        })
    );
    // The cap needs a P-alpha EoS with a crush pressure above COMPRAT fc/3.
    assert_eq!(
        broken(&|m| m.eos = Eos::Linear(stoss_kernel::eos::LinearEos {
            bulk_modulus: 21.5e9
        })),
        Err(ParameterError::Inconsistent {
            field: "elastic_cap",
            other: "eos"
        })
    );
    assert_eq!(
        broken(&|m| {
            if let Eos::PAlpha(eos) = &mut m.eos {
                eos.crush_pressure = 20.0e6;
            }
        }),
        Err(ParameterError::Inconsistent {
            field: "crush_pressure",
            other: "compressive_elastic_ratio"
        })
    );
    assert_eq!(
        broken(&|m| m.erosion_plastic_strain = Some(0.0)),
        Err(ParameterError::NotPositive {
            field: "erosion_plastic_strain",
            value: 0.0
        })
    );
    // Without the cap any EoS is accepted.
    assert_eq!(
        broken(&|m| {
            m.parameters.elastic_cap = false;
            m.eos = Eos::Linear(stoss_kernel::eos::LinearEos {
                bulk_modulus: 21.5e9,
            });
        }),
        Ok(())
    );
    // Drivers refuse invalid materials.
    let mut bad = good;
    bad.parameters.residual_m = 1.5;
    let mut state = bad.initial_state(293.0);
    let error = uniaxial_stress(
        &bad,
        &mut state,
        &UniaxialStressLoading {
            strain_rate: 1.0,
            final_strain: -0.001,
            steps: 10,
        },
        &mut History::default(),
    );
    assert!(matches!(
        error,
        Err(DriverError::Parameter(ParameterError::OutOfRange {
            field: "residual_m",
            ..
        }))
    ));
    // Bad step input: typed error, state untouched.
    let mut state = good.initial_state(293.0);
    let before = state;
    let input = StepInput {
        strain_increment: [f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0],
        dt: 1e-6,
        relative_volume: 1.0,
    };
    assert_eq!(
        update(&good, &mut state, &input),
        Err(UpdateError::NonFiniteInput)
    );
    let input = StepInput {
        strain_increment: [0.0; 6],
        dt: 0.0,
        relative_volume: 1.0,
    };
    assert_eq!(
        update(&good, &mut state, &input),
        Err(UpdateError::NonPositiveTimeStep)
    );
    let input = StepInput {
        strain_increment: [0.0; 6],
        dt: 1e-6,
        relative_volume: -1.0,
    };
    assert_eq!(
        update(&good, &mut state, &input),
        Err(UpdateError::NonPositiveVolume)
    );
    assert_eq!(state, before);
}

#[test]
fn updates_are_deterministic_and_the_tangent_is_elastic_inside_the_surface() {
    // GOAL: the same inputs give bit-identical states; inside the elastic range the
    //   finite-difference tangent is the isotropic elastic one, K = (1 + mu) dp/dmu and G.
    // SETUP: one small compressive step from the virgin state, repeated.
    // REFERENCE: exact equality; tangent entries within 1e-4 relative of lambda + 2G,
    //   lambda, 2G (the energy term of the EoS couples p to the volumetric work at
    //   ~1e-5 relative).
    let material = RhtMaterial::HPC_92MPA;
    let increment = [-2e-5, 4e-6, 3e-6, 1e-6, 0.0, 0.0];
    let input = StepInput {
        strain_increment: increment,
        dt: 1e-6,
        relative_volume: libm::exp(tensor::trace(&increment)),
    };
    let mut a = material.initial_state(293.0);
    let mut b = material.initial_state(293.0);
    let out_a = update(&material, &mut a, &input).unwrap();
    let out_b = update(&material, &mut b, &input).unwrap();
    assert_eq!(a, b);
    assert_eq!(out_a, out_b);
    assert_eq!(a.flags.0 & StateFlags::PLASTIC, 0);
    let mut state = material.initial_state(293.0);
    let mut tangent = [[0.0; 6]; 6];
    stoss_kernel::rht::update_with_tangent(&material, &mut state, &input, &mut tangent).unwrap();
    assert_eq!(state, a);
    let Eos::PAlpha(eos) = material.eos else {
        unreachable!()
    };
    let mu = 1.0 / input.relative_volume - 1.0;
    let bulk = (1.0 + mu) * eos.evaluate(mu, eos.initial_distension).0.d_base_d_mu;
    let g = material.parameters.shear_modulus;
    let lambda = bulk - 2.0 / 3.0 * g;
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    assert!(
        rel(tangent[0][0], lambda + 2.0 * g) < 1e-4,
        "{}",
        tangent[0][0]
    );
    assert!(rel(tangent[0][1], lambda) < 1e-4, "{}", tangent[0][1]);
    assert!(rel(tangent[3][3], 2.0 * g) < 1e-4, "{}", tangent[3][3]);
    assert!(tangent[3][0].abs() < 1e-4 * g);
}
