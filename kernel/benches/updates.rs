//! Throughput of the stress update, in updates per second, for each strength model (JC, ZA
//! BCC, MJC, TJC) and rate treatment (implicit eq. 3.8, lagged eq. 3.7).
//!
//! Every benchmark iteration runs [`BLOCK`] updates of one material point; the item counter
//! is updates, so divan reports updates/s. Plastic loading is uniaxial compressive strain,
//! `deps_xx = -1e-5` per step in `dt = 1e-8 s` (axial rate 1e3 /s), starting from developed
//! plastic flow (first yield plus [`PRELOAD_PLASTIC_STEPS`] steps):
//!
//! - `path`: [`BLOCK`] consecutive updates. Implicit: every update is a plastic return
//!   (asserted before timing). Lagged: the path alternates plastic/elastic updates (the eq. 3.7
//!   rate-lag defect), so half of them are returns (asserted).
//! - `plastic_return`: [`BLOCK`] updates, each from the same state whose next step yields, so
//!   every update is a plastic return for both treatments.
//! - `elastic`: [`BLOCK`] consecutive updates of `deps_xx = 1e-9` from the virgin state, far
//!   below yield (asserted): predictor and yield check only.
//!
//! Run with `cargo bench -p stoss-kernel --bench updates`; results are in
//! `docs/benchmarks.md`.

use divan::counter::ItemsCount;
use divan::{black_box, Bencher};
use stoss_kernel::math::exp;
use stoss_kernel::strength::{
    CrystalStructure, JohnsonCook, ModifiedJohnsonCook, TwoRateJohnsonCook, ZerilliArmstrong,
};
use stoss_kernel::{update, Material, MaterialState, RateTreatment, StepInput};

/// Consecutive updates per benchmark iteration.
const BLOCK: u32 = 1000;

/// Room temperature (K) of the initial state.
const ROOM_TEMPERATURE: f64 = 298.0;

/// Both rate treatments, as divan arguments.
const TREATMENTS: [RateTreatment; 2] = [RateTreatment::Implicit, RateTreatment::Lagged];

/// Johnson & Cook (1985) 4340 steel (the kernel's constants).
fn jc() -> Material {
    Material::STEEL_4340.with_strength(JohnsonCook::STEEL_4340)
}

/// Zerilli-Armstrong BCC with the Zerilli & Armstrong (1987) Armco-iron activation and
/// hardening constants (C1 1033 MPa, C3 0.00698 /K, C4 0.000415 /K, C5 266 MPa, n 0.289).
/// The athermal stress (grain-size term) is set to 65 MPa by us, a typical Hall-Petch
/// contribution for Armco iron; elasticity, density, EoS and heating are those of
/// `Material::STEEL_4340`. The constants only set how far the return has to go, not its cost.
fn za_bcc() -> Material {
    Material::STEEL_4340.with_strength(ZerilliArmstrong {
        structure: CrystalStructure::Bcc,
        athermal_stress: 65.0e6,
        c1: 1033.0e6,
        c2: 0.0,
        c3: 0.00698,
        c4: 0.000415,
        c5: 266.0e6,
        exponent: 0.289,
        reference_rate: 1.0,
    })
}

/// Modified Johnson-Cook: 4340 JC power hardening plus two Voce terms (Q1 100 MPa, c1 10;
/// Q2 50 MPa, c2 100), power-law rate beta 0.01 (e0 1 /s), JC 4340 thermal softening.
fn mjc() -> Material {
    Material::STEEL_4340.with_strength(ModifiedJohnsonCook {
        yield_stress: 792.0e6,
        hardening_modulus: 510.0e6,
        hardening_exponent: 0.26,
        saturation_stress_1: 100.0e6,
        saturation_rate_1: 10.0,
        saturation_stress_2: 50.0e6,
        saturation_rate_2: 100.0,
        rate_exponent: 0.01,
        reference_rate: 1.0,
        thermal_exponent: 1.03,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    })
}

/// Two-rate Johnson-Cook: the MJC hardening and thermal terms above with rate factor
/// `(1 + e/1e-3)^0.005 (1 + e/1e3)^0.05`.
fn tjc() -> Material {
    Material::STEEL_4340.with_strength(TwoRateJohnsonCook {
        yield_stress: 792.0e6,
        hardening_modulus: 510.0e6,
        hardening_exponent: 0.26,
        saturation_stress_1: 100.0e6,
        saturation_rate_1: 10.0,
        saturation_stress_2: 50.0e6,
        saturation_rate_2: 100.0,
        rate_exponent_1: 0.005,
        reference_rate_1: 1.0e-3,
        rate_exponent_2: 0.05,
        reference_rate_2: 1.0e3,
        thermal_exponent: 1.03,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    })
}

/// Uniaxial-strain step with axial increment `axial` from relative volume `volume`.
fn uniaxial_step(axial: f64, dt: f64, volume: f64) -> StepInput {
    StepInput {
        strain_increment: [axial, 0.0, 0.0, 0.0, 0.0, 0.0],
        dt,
        relative_volume: volume * exp(axial),
    }
}

/// The plastic-loading increment: uniaxial compressive strain 1e-5 in 1e-8 s.
const PLASTIC_AXIAL: f64 = -1.0e-5;
const PLASTIC_DT: f64 = 1.0e-8;

/// Run one block of updates from `start`, advancing the relative volume each step.
#[inline(always)]
fn run_block(material: &Material, start: MaterialState, axial: f64, dt: f64) -> MaterialState {
    let mut state = start;
    for _ in 0..BLOCK {
        let input = uniaxial_step(axial, dt, state.relative_volume);
        update(material, &mut state, black_box(&input)).expect("update failed");
    }
    state
}

/// Steps taken after the first plastic step before a block starts, so blocks sample
/// developed plastic flow rather than the elastic-plastic transition.
const PRELOAD_PLASTIC_STEPS: u32 = 300;

/// `material` with `treatment`, validated.
fn with_treatment(material: Material, treatment: RateTreatment) -> Material {
    let material = Material {
        rate_treatment: treatment,
        ..material
    };
    material.validate().expect("invalid benchmark material");
    material
}

/// One plastic-loading step; returns whether it was plastic.
fn plastic_step(material: &Material, state: &mut MaterialState) -> bool {
    let input = uniaxial_step(PLASTIC_AXIAL, PLASTIC_DT, state.relative_volume);
    let output = update(material, state, &input).expect("update failed");
    output.plastic_increment > 0.0
}

/// State after loading to first yield and [`PRELOAD_PLASTIC_STEPS`] further steps.
fn preloaded(material: &Material) -> MaterialState {
    let mut state = MaterialState::initial(ROOM_TEMPERATURE);
    let mut steps = 0;
    while !plastic_step(material, &mut state) {
        steps += 1;
        assert!(steps < 10 * BLOCK, "material never yielded");
    }
    for _ in 0..PRELOAD_PLASTIC_STEPS {
        plastic_step(material, &mut state);
    }
    state
}

/// Number of plastic updates in one block from `start`.
fn plastic_count(material: &Material, start: MaterialState) -> u32 {
    let mut state = start;
    (0..BLOCK)
        .map(|_| u32::from(plastic_step(material, &mut state)))
        .sum()
}

fn bench_path(bencher: Bencher, material: Material, treatment: RateTreatment) {
    let material = with_treatment(material, treatment);
    let start = preloaded(&material);
    let plastic = plastic_count(&material, start);
    match treatment {
        RateTreatment::Implicit => assert_eq!(plastic, BLOCK, "elastic step in an implicit block"),
        // Eq. 3.7 checks yield with the previous step's rate: a plastic step raises that rate,
        // the next check fails, and the path alternates plastic/elastic.
        RateTreatment::Lagged => assert!(2 * plastic >= BLOCK - 2, "lagged block mostly elastic"),
    }
    bencher.counter(ItemsCount::new(BLOCK)).bench_local(|| {
        run_block(
            black_box(&material),
            black_box(start),
            PLASTIC_AXIAL,
            PLASTIC_DT,
        )
    });
}

fn bench_return(bencher: Bencher, material: Material, treatment: RateTreatment) {
    let material = with_treatment(material, treatment);
    let mut start = preloaded(&material);
    // Advance to a state whose next plastic-loading step yields.
    loop {
        let mut probe = start;
        if plastic_step(&material, &mut probe) {
            break;
        }
        start = probe;
    }
    let input = uniaxial_step(PLASTIC_AXIAL, PLASTIC_DT, start.relative_volume);
    bencher.counter(ItemsCount::new(BLOCK)).bench_local(|| {
        for _ in 0..BLOCK {
            let mut state = black_box(start);
            update(black_box(&material), &mut state, black_box(&input)).expect("update failed");
            black_box(state);
        }
    });
}

/// [`BLOCK`] consecutive plastic-loading updates along uniaxial strain, from developed plastic
/// flow. Implicit: every update is a plastic return (asserted). Lagged: the path alternates
/// between plastic and elastic updates (the eq. 3.7 defect), so about half are returns.
mod path {
    use super::*;

    #[divan::bench(args = TREATMENTS)]
    fn jc_4340(bencher: Bencher, treatment: RateTreatment) {
        bench_path(bencher, jc(), treatment);
    }

    #[divan::bench(args = TREATMENTS)]
    fn za_bcc(bencher: Bencher, treatment: RateTreatment) {
        bench_path(bencher, super::za_bcc(), treatment);
    }

    #[divan::bench(args = TREATMENTS)]
    fn mjc(bencher: Bencher, treatment: RateTreatment) {
        bench_path(bencher, super::mjc(), treatment);
    }

    #[divan::bench(args = TREATMENTS)]
    fn tjc(bencher: Bencher, treatment: RateTreatment) {
        bench_path(bencher, super::tjc(), treatment);
    }
}

/// [`BLOCK`] updates, each from the same state whose next step yields: every update is a
/// plastic return, for both treatments.
mod plastic_return {
    use super::*;

    #[divan::bench(args = TREATMENTS)]
    fn jc_4340(bencher: Bencher, treatment: RateTreatment) {
        bench_return(bencher, jc(), treatment);
    }

    #[divan::bench(args = TREATMENTS)]
    fn za_bcc(bencher: Bencher, treatment: RateTreatment) {
        bench_return(bencher, super::za_bcc(), treatment);
    }

    #[divan::bench(args = TREATMENTS)]
    fn mjc(bencher: Bencher, treatment: RateTreatment) {
        bench_return(bencher, super::mjc(), treatment);
    }

    #[divan::bench(args = TREATMENTS)]
    fn tjc(bencher: Bencher, treatment: RateTreatment) {
        bench_return(bencher, super::tjc(), treatment);
    }
}

/// Elastic-only updates (predictor and yield check, no return), implicit rate treatment.
mod elastic {
    use super::*;

    const ELASTIC_AXIAL: f64 = 1.0e-9;
    const ELASTIC_DT: f64 = 1.0e-8;

    fn bench_elastic(bencher: Bencher, material: Material) {
        material.validate().expect("invalid benchmark material");
        let start = MaterialState::initial(ROOM_TEMPERATURE);
        let end = run_block(&material, start, ELASTIC_AXIAL, ELASTIC_DT);
        assert_eq!(end.plastic_strain, 0.0, "elastic block yielded");
        bencher.counter(ItemsCount::new(BLOCK)).bench_local(|| {
            run_block(
                black_box(&material),
                black_box(start),
                ELASTIC_AXIAL,
                ELASTIC_DT,
            )
        });
    }

    #[divan::bench]
    fn jc_4340(bencher: Bencher) {
        bench_elastic(bencher, jc());
    }

    #[divan::bench]
    fn za_bcc(bencher: Bencher) {
        bench_elastic(bencher, super::za_bcc());
    }

    #[divan::bench]
    fn mjc(bencher: Bencher) {
        bench_elastic(bencher, super::mjc());
    }

    #[divan::bench]
    fn tjc(bencher: Bencher) {
        bench_elastic(bencher, super::tjc());
    }
}

fn main() {
    divan::main();
}
