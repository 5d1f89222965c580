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
//! - `block`: [`POINTS`] independent points advanced together, [`BLOCK_STEPS`] steps per
//!   iteration, each point at its own axial rate (1e3 /s to 1.5e3 /s) from its own developed
//!   flow (first yield plus [`BLOCK_PRELOAD_PLASTIC_STEPS`] steps, the middle of the `path`
//!   case's strains); every update is a plastic return (asserted). This is how a host calls the kernel (a
//!   VUMAT's block, a solver's element loop): the points do not wait on one another, so it
//!   measures throughput, where `path` measures one point's chain of dependent updates.
//! - `elastic`: [`BLOCK`] consecutive updates of `deps_xx = 1e-9` from the virgin state, far
//!   below yield (asserted): predictor and yield check only.
//!
//! Equations of state (`eos` module): [`EOS_BLOCK`] calls of [`Eos::evaluate`] over a sweep
//! of compressions per iteration, counted as evaluations, for every EoS (history-dependent
//! ones on their loading and unloading branches).
//!
//! RHT concrete (`rht` module, [`RhtMaterial::HPC_92MPA`]): updates in uniaxial compressive
//! strain, elastic (far below the elastic limit, [`BLOCK`] per iteration), hardening returns
//! (between the elastic limit and the failure surface, `D = 0`) and damaging steps
//! (`0 < D < 1`, each step plastic), [`SHORT_BLOCK`] per iteration, all asserted before
//! timing.
//!
//! K&C concrete (`kc` module): elastic updates and a softening path past the peak of the
//! damage function, [`BLOCK`] per iteration, asserted before timing.
//!
//! The costly cases (RHT plastic steps and P-alpha compaction, about 5 us each) run
//! [`SHORT_BLOCK`] per iteration so that a sample (about 0.5 ms) fits in a scheduler time
//! slice: on a loaded machine, samples of several milliseconds are nearly all preempted and
//! their median measures the load, not the code.
//!
//! `grouped`: the `block` case through `update_block`, the points advanced `LANES` at a time
//! (`stoss_kernel::j2::lanes`). `-- --alternate` times the `block` case both ways alternately
//! in one process (below).
//!
//! Run with `cargo bench -p stoss-kernel --bench updates`; results are in
//! `docs/benchmarks.md`.

use divan::counter::ItemsCount;
use divan::{black_box, Bencher};
use stoss_kernel::eos::{Eos, Jwl, LinearEos, MieGruneisen, Polynomial, TabulatedCompaction};
use stoss_kernel::math::{exp, ln};
use stoss_kernel::rht::RhtMaterial;
use stoss_kernel::strength::{
    JohnsonCook, KhanHuangLiang, MechanicalThresholdStress, ModifiedJohnsonCook,
    PrestonTonksWallace, Strength, TwoRateJohnsonCook, VoceKocks, ZerilliArmstrong,
};
use stoss_kernel::{
    update, update_block, Material, MaterialState, RateTreatment, StateFlags, StepInput,
    UpdateError,
};

/// Consecutive updates per benchmark iteration.
const BLOCK: u32 = 1000;

/// Updates or evaluations per iteration of the costly (about 5 us) cases.
const SHORT_BLOCK: u32 = 100;

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
    Material::STEEL_4340.with_strength(ZerilliArmstrong::ARMCO_IRON)
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

/// Repeated uniaxial-strain steps: axial increment `axial` in `dt`, the relative volume
/// multiplied by `exp(axial)` each step (computed once: the host's volume integration is
/// not the kernel's cost).
#[derive(Clone, Copy)]
struct Loading {
    axial: f64,
    dt: f64,
    volume_factor: f64,
}

impl Loading {
    fn new(axial: f64, dt: f64) -> Self {
        Self {
            axial,
            dt,
            volume_factor: exp(axial),
        }
    }

    /// The step from relative volume `volume`.
    #[inline(always)]
    fn step(&self, volume: f64) -> StepInput {
        StepInput {
            strain_increment: [self.axial, 0.0, 0.0, 0.0, 0.0, 0.0],
            dt: self.dt,
            relative_volume: volume * self.volume_factor,
        }
    }
}

/// Uniaxial-strain step with axial increment `axial` from relative volume `volume`.
fn uniaxial_step(axial: f64, dt: f64, volume: f64) -> StepInput {
    Loading::new(axial, dt).step(volume)
}

/// The plastic-loading increment: uniaxial compressive strain 1e-5 in 1e-8 s.
const PLASTIC_AXIAL: f64 = -1.0e-5;
const PLASTIC_DT: f64 = 1.0e-8;

/// Run one block of updates from `start`, advancing the relative volume each step.
#[inline(always)]
fn run_block(material: &Material, start: MaterialState, axial: f64, dt: f64) -> MaterialState {
    let mut state = start;
    let loading = Loading::new(axial, dt);
    for _ in 0..BLOCK {
        let input = loading.step(state.relative_volume);
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

/// Points in a [`block`] benchmark: an Abaqus/Explicit VUMAT block.
const POINTS: usize = 128;

/// Steps per iteration of a [`block`] benchmark.
const BLOCK_STEPS: u32 = 8;

/// Plastic steps before a [`block`] benchmark's steps: the middle of the strains the `path`
/// benchmark spans ([`PRELOAD_PLASTIC_STEPS`] to [`PRELOAD_PLASTIC_STEPS`] + [`BLOCK`]).
const BLOCK_PRELOAD_PLASTIC_STEPS: u32 = PRELOAD_PLASTIC_STEPS + BLOCK / 2;

/// The axial increment of block point `point`: 1e3 /s to 1.5e3 /s.
fn block_axial(point: usize) -> f64 {
    PLASTIC_AXIAL * (1.0 + 0.5 * point as f64 / POINTS as f64)
}

/// The [`block`] case's points, each from first yield plus [`BLOCK_PRELOAD_PLASTIC_STEPS`]
/// plastic steps at its own rate.
fn block_start(material: &Material) -> Vec<MaterialState> {
    (0..POINTS)
        .map(|point| {
            let mut state = MaterialState::initial(ROOM_TEMPERATURE);
            let mut plastic = 0;
            while plastic < BLOCK_PRELOAD_PLASTIC_STEPS {
                let input = uniaxial_step(block_axial(point), PLASTIC_DT, state.relative_volume);
                let output = update(material, &mut state, &input).expect("update failed");
                plastic += u32::from(output.plastic_increment > 0.0);
            }
            state
        })
        .collect()
}

fn bench_block(bencher: Bencher, material: Material, treatment: RateTreatment) {
    bench_points(bencher, material, treatment, false);
}

/// The [`block`] case through [`update_block`]: the points advanced [`stoss_kernel::LANES`] at a time.
fn bench_grouped(bencher: Bencher, material: Material, treatment: RateTreatment) {
    bench_points(bencher, material, treatment, true);
}

fn bench_points(bencher: Bencher, material: Material, treatment: RateTreatment, grouped: bool) {
    let material = with_treatment(material, treatment);
    let start = block_start(&material);
    let loadings: Vec<Loading> = (0..POINTS)
        .map(|point| Loading::new(block_axial(point), PLASTIC_DT))
        .collect();
    let mut inputs = vec![uniaxial_step(0.0, PLASTIC_DT, 1.0); POINTS];
    let mut results = vec![Err(UpdateError::NonFiniteInput); POINTS];
    let mut advance = |states: &mut [MaterialState]| -> u32 {
        let mut plastic = 0;
        for _ in 0..BLOCK_STEPS {
            if grouped {
                for ((input, state), loading) in inputs.iter_mut().zip(&*states).zip(&loadings) {
                    *input = loading.step(state.relative_volume);
                }
                update_block(black_box(&material), states, &inputs, &mut results);
                for result in &results {
                    let output = result.as_ref().expect("update failed");
                    plastic += u32::from(output.plastic_increment > 0.0);
                }
                continue;
            }
            for (state, loading) in states.iter_mut().zip(&loadings) {
                let input = loading.step(state.relative_volume);
                let output =
                    update(black_box(&material), state, black_box(&input)).expect("update failed");
                plastic += u32::from(output.plastic_increment > 0.0);
            }
        }
        plastic
    };
    if treatment == RateTreatment::Implicit {
        let plastic = advance(&mut start.clone());
        assert_eq!(
            plastic,
            BLOCK_STEPS * POINTS as u32,
            "elastic step in a block"
        );
    }
    bencher
        .counter(ItemsCount::new(BLOCK_STEPS as usize * POINTS))
        .with_inputs(|| start.clone())
        .bench_local_refs(|states| advance(states));
}

/// The [`block`] cases through [`update_block`] ([`stoss_kernel::LANES`] points at a time).
mod grouped {
    use super::*;

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn jc_4340(bencher: Bencher, treatment: RateTreatment) {
        bench_grouped(bencher, jc(), treatment);
    }

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn za_bcc(bencher: Bencher, treatment: RateTreatment) {
        bench_grouped(bencher, super::za_bcc(), treatment);
    }

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn mjc(bencher: Bencher, treatment: RateTreatment) {
        bench_grouped(bencher, super::mjc(), treatment);
    }

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn tjc(bencher: Bencher, treatment: RateTreatment) {
        bench_grouped(bencher, super::tjc(), treatment);
    }
}

/// [`POINTS`] independent points advanced together along uniaxial strain, [`BLOCK_STEPS`]
/// steps per iteration, from developed plastic flow: the throughput of a host's block.
mod block {
    use super::*;

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn jc_4340(bencher: Bencher, treatment: RateTreatment) {
        bench_block(bencher, jc(), treatment);
    }

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn za_bcc(bencher: Bencher, treatment: RateTreatment) {
        bench_block(bencher, super::za_bcc(), treatment);
    }

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn mjc(bencher: Bencher, treatment: RateTreatment) {
        bench_block(bencher, super::mjc(), treatment);
    }

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn tjc(bencher: Bencher, treatment: RateTreatment) {
        bench_block(bencher, super::tjc(), treatment);
    }

    /// A family of issue 50 on 4340's elasticity (the constants only set how far the return
    /// goes; these families report no bounded curvature, so their returns take safeguarded
    /// Newton steps).
    fn on_4340(strength: Strength) -> Material {
        Material { strength, ..jc() }
    }

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn ptw_tantalum(bencher: Bencher, treatment: RateTreatment) {
        bench_block(
            bencher,
            on_4340(PrestonTonksWallace::TANTALUM.into()),
            treatment,
        );
    }

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn khl_illustrative(bencher: Bencher, treatment: RateTreatment) {
        bench_block(
            bencher,
            on_4340(KhanHuangLiang::ILLUSTRATIVE.into()),
            treatment,
        );
    }

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn vk_illustrative(bencher: Bencher, treatment: RateTreatment) {
        bench_block(bencher, on_4340(VoceKocks::ILLUSTRATIVE.into()), treatment);
    }

    #[divan::bench(args = [RateTreatment::Implicit])]
    fn mts_copper(bencher: Bencher, treatment: RateTreatment) {
        bench_block(
            bencher,
            on_4340(MechanicalThresholdStress::COPPER.into()),
            treatment,
        );
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
        bench_elastic_block(bencher, &material, start);
    }

    /// Time a block of elastic increments from `start`.
    fn bench_elastic_block(bencher: Bencher, material: &Material, start: MaterialState) {
        bencher.counter(ItemsCount::new(BLOCK)).bench_local(|| {
            run_block(
                black_box(material),
                black_box(start),
                ELASTIC_AXIAL,
                ELASTIC_DT,
            )
        });
    }

    /// Elastic updates from developed, heated plastic flow, unloaded by an axial strain of
    /// 1e-3 (below the quasi-static surface: the state on the rate-enhanced surface would
    /// relax plastically), then small unloading increments: the yield check evaluates the
    /// hardening and thermal terms at `eps_p > 0`, `T > Tr` (two `pow` for JC), unlike the
    /// virgin state where both are 1 without a call.
    fn bench_elastic_after_flow(bencher: Bencher, material: Material) {
        material.validate().expect("invalid benchmark material");
        let mut start = preloaded(&material);
        let unload = uniaxial_step(1.0e-3, ELASTIC_DT, start.relative_volume);
        let output = update(&material, &mut start, &unload).expect("unloading failed");
        assert_eq!(output.plastic_increment, 0.0, "unloading yielded");
        assert!(start.plastic_strain > 0.0 && start.temperature > ROOM_TEMPERATURE);
        let end = run_block(&material, start, ELASTIC_AXIAL, ELASTIC_DT);
        assert_eq!(
            end.plastic_strain, start.plastic_strain,
            "unloading block yielded"
        );
        bench_elastic_block(bencher, &material, start);
    }

    #[divan::bench]
    fn jc_4340(bencher: Bencher) {
        bench_elastic(bencher, jc());
    }

    #[divan::bench]
    fn jc_4340_after_flow(bencher: Bencher) {
        bench_elastic_after_flow(bencher, jc());
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

/// EoS evaluations per benchmark iteration.
const EOS_BLOCK: usize = 1000;

/// Pressure evaluations per second: [`EOS_BLOCK`] calls of [`Eos::evaluate`] at
/// compressions spread evenly over a range, each from the same history value (so every call
/// of a history-dependent EoS is on the branch named by the benchmark; asserted before
/// timing). The pressure at `E` = 1 MJ/m^3 is formed from the returned terms.
mod eos {
    use super::*;

    const ENERGY: f64 = 1.0e6;

    /// `EOS_BLOCK` compressions from `from` to `to`.
    fn sweep(from: f64, to: f64) -> Vec<f64> {
        sweep_of(EOS_BLOCK, from, to)
    }

    /// `count` compressions from `from` to `to`.
    fn sweep_of(count: usize, from: f64, to: f64) -> Vec<f64> {
        (0..count)
            .map(|i| from + (to - from) * i as f64 / (count - 1) as f64)
            .collect()
    }

    /// Time the sweep; `branch` checks each `(mu, history in, history out)` beforehand.
    fn bench_sweep(
        bencher: Bencher,
        eos: Eos,
        mus: Vec<f64>,
        history: f64,
        branch: impl Fn(f64, f64, f64) -> bool,
    ) {
        eos.validate().expect("invalid benchmark EoS");
        for &mu in &mus {
            let (terms, next) = eos.evaluate(mu, history);
            assert!(terms.pressure(ENERGY).is_finite(), "mu {mu}");
            assert!(
                branch(mu, history, next),
                "mu {mu}: not on the benchmarked branch"
            );
        }
        bencher.counter(ItemsCount::new(mus.len())).bench_local(|| {
            let eos = black_box(&eos);
            let mut sum = 0.0;
            for &mu in black_box(&mus) {
                let (terms, next) = eos.evaluate(mu, black_box(history));
                sum += terms.pressure(ENERGY) + next;
            }
            sum
        });
    }

    fn any(_: f64, _: f64, _: f64) -> bool {
        true
    }

    /// Linear, K 159 GPa, mu -0.05..0.2.
    #[divan::bench]
    fn linear(bencher: Bencher) {
        let eos = Eos::Linear(LinearEos {
            bulk_modulus: 159.0e9,
        });
        bench_sweep(bencher, eos, sweep(-0.05, 0.2), 0.0, any);
    }

    /// Mie-Grueneisen, Steinberg 4340 (C 4578 m/s, S1 1.33, gamma0 1.67, a 0.43),
    /// mu -0.05..0.3 (both branches).
    #[divan::bench]
    fn mie_gruneisen(bencher: Bencher) {
        let eos = Eos::MieGruneisen(MieGruneisen {
            reference_density: 7810.0,
            sound_speed: 4578.0,
            s1: 1.33,
            s2: 0.0,
            s3: 0.0,
            gamma0: 1.67,
            volume_correction: 0.43,
        });
        bench_sweep(bencher, eos, sweep(-0.05, 0.3), 0.0, any);
    }

    /// Polynomial, the RHT HPC matrix (A1 24.4, A2 39.58, A3 9.04 GPa, B0 = B1 = 1.22),
    /// mu -0.05..0.3.
    #[divan::bench]
    fn polynomial(bencher: Bencher) {
        let eos = Eos::Polynomial(Polynomial {
            a1: 24.4e9,
            a2: 39.58e9,
            a3: 9.04e9,
            b0: 1.22,
            b1: 1.22,
            t1: 24.4e9,
            t2: 0.0,
        });
        bench_sweep(bencher, eos, sweep(-0.05, 0.3), 0.0, any);
    }

    /// JWL C-4, relative volume 2.5 to 0.67 (mu -0.6..0.5): two exponentials per call.
    #[divan::bench]
    fn jwl_c4(bencher: Bencher) {
        bench_sweep(bencher, Eos::Jwl(Jwl::C4), sweep(-0.6, 0.5), 0.0, any);
    }

    /// Tabulated compaction, seed 001 table 5.2: loading from the virgin state
    /// (`ln(1 + mu)` and the segment search), mu 0..0.075 (through all 8 points).
    #[divan::bench]
    fn tabulated_loading(bencher: Bencher) {
        let eos = Eos::TabulatedCompaction(TabulatedCompaction::CONCRETE_FOI_TABLE_5_2);
        // Loading: the new maximum strain is the current one, ln(1 + mu).
        bench_sweep(bencher, eos, sweep(0.0, 0.075), 0.0, |mu, _, next| {
            next == ln(1.0 + mu)
        });
    }

    /// Tabulated compaction, table 5.2: unloading below a maximum strain of 0.0726.
    #[divan::bench]
    fn tabulated_unloading(bencher: Bencher) {
        let eos = Eos::TabulatedCompaction(TabulatedCompaction::CONCRETE_FOI_TABLE_5_2);
        bench_sweep(
            bencher,
            eos,
            sweep(0.0, 0.075),
            0.0726,
            |_, before, after| after == before,
        );
    }

    fn p_alpha() -> Eos {
        RhtMaterial::HPC_92MPA.eos
    }

    /// P-alpha (RHT HPC EoS): elastic at alpha0, below the 61.3 MPa crush pressure
    /// (mu 0..0.0025).
    #[divan::bench]
    fn p_alpha_elastic(bencher: Bencher) {
        let eos = p_alpha();
        let alpha0 = eos.initial_history();
        bench_sweep(
            bencher,
            eos,
            sweep(0.0, 0.0025),
            alpha0,
            |_, before, after| after == before,
        );
    }

    /// P-alpha: compacting from alpha0 (mu 0.01..0.2, between crush and lock): every call
    /// resolves alpha by bisection. [`SHORT_BLOCK`] evaluations per iteration.
    #[divan::bench]
    fn p_alpha_compacting(bencher: Bencher) {
        let eos = p_alpha();
        let alpha0 = eos.initial_history();
        bench_sweep(
            bencher,
            eos,
            sweep_of(SHORT_BLOCK as usize, 0.01, 0.2),
            alpha0,
            |_, before, after| after < before && after > 1.0,
        );
    }

    /// P-alpha: unloading at the distension reached at mu 0.12 (mu 0..0.12), alpha kept.
    #[divan::bench]
    fn p_alpha_unloading(bencher: Bencher) {
        let eos = p_alpha();
        let (_, alpha) = eos.evaluate(0.12, eos.initial_history());
        bench_sweep(bencher, eos, sweep(0.0, 0.12), alpha, |_, before, after| {
            after == before
        });
    }
}

/// RHT concrete updates per second ([`RhtMaterial::HPC_92MPA`], `stoss_kernel::rht::update`).
/// Loading is uniaxial compressive strain, `deps_xx = -1e-5` per step in `dt = 1e-8 s`
/// (1e3 /s) for the plastic cases.
mod rht {
    use super::*;
    use stoss_kernel::rht;

    fn material() -> RhtMaterial {
        let material = RhtMaterial::HPC_92MPA;
        material.validate().expect("invalid benchmark material");
        material
    }

    /// One step; returns whether it was plastic.
    fn step(material: &RhtMaterial, state: &mut MaterialState, axial: f64, dt: f64) -> bool {
        let input = uniaxial_step(axial, dt, state.relative_volume);
        rht::update(material, state, &input).expect("RHT update failed");
        state.flags.0 & StateFlags::PLASTIC != 0
    }

    /// State after `steps` plastic-loading steps from the virgin state.
    fn preloaded(material: &RhtMaterial, steps: u32) -> MaterialState {
        let mut state = material.initial_state(ROOM_TEMPERATURE);
        for _ in 0..steps {
            step(material, &mut state, PLASTIC_AXIAL, PLASTIC_DT);
        }
        state
    }

    /// [`BLOCK`] consecutive updates of `deps_xx = -1e-9` from the virgin state (stress
    /// below 0.05 MPa, far inside the elastic surface; asserted).
    #[divan::bench]
    fn elastic(bencher: Bencher) {
        let material = material();
        let start = material.initial_state(ROOM_TEMPERATURE);
        let mut state = start;
        for _ in 0..BLOCK {
            assert!(
                !step(&material, &mut state, -1.0e-9, 1.0e-8),
                "elastic block yielded"
            );
        }
        bencher.counter(ItemsCount::new(BLOCK)).bench_local(|| {
            let material = black_box(&material);
            let mut state = black_box(start);
            for _ in 0..BLOCK {
                let input = uniaxial_step(-1.0e-9, 1.0e-8, state.relative_volume);
                rht::update(material, &mut state, black_box(&input)).expect("update failed");
            }
            state
        });
    }

    /// [`SHORT_BLOCK`] updates, each from the same state at axial strain -0.5 % (500
    /// plastic-loading steps): a hardening return between the elastic limit and the failure surface, `D = 0`
    /// (asserted).
    #[divan::bench]
    fn hardening_return(bencher: Bencher) {
        let material = material();
        let start = preloaded(&material, 500);
        let mut probe = start;
        assert!(
            step(&material, &mut probe, PLASTIC_AXIAL, PLASTIC_DT),
            "not plastic"
        );
        assert!(probe.plastic_strain > start.plastic_strain && probe.damage == 0.0);
        let input = uniaxial_step(PLASTIC_AXIAL, PLASTIC_DT, start.relative_volume);
        bencher
            .counter(ItemsCount::new(SHORT_BLOCK))
            .bench_local(|| {
                for _ in 0..SHORT_BLOCK {
                    let mut state = black_box(start);
                    rht::update(black_box(&material), &mut state, black_box(&input))
                        .expect("update failed");
                    black_box(state);
                }
            });
    }

    /// [`SHORT_BLOCK`] consecutive updates from developed damage (first damaging step plus
    /// [`PRELOAD_PLASTIC_STEPS`] plastic-loading steps): every step plastic and damaging,
    /// `0 < D < 1` throughout (asserted); P-alpha compaction on every step.
    #[divan::bench]
    fn damaging_path(bencher: Bencher) {
        let material = material();
        let mut start = material.initial_state(ROOM_TEMPERATURE);
        let mut steps = 0;
        while start.damage == 0.0 {
            step(&material, &mut start, PLASTIC_AXIAL, PLASTIC_DT);
            steps += 1;
            assert!(steps < 100 * BLOCK, "no damage");
        }
        for _ in 0..PRELOAD_PLASTIC_STEPS {
            step(&material, &mut start, PLASTIC_AXIAL, PLASTIC_DT);
        }
        let mut state = start;
        assert!(start.damage > 0.0, "no damage at the start of the block");
        for _ in 0..SHORT_BLOCK {
            let before = state;
            assert!(
                step(&material, &mut state, PLASTIC_AXIAL, PLASTIC_DT),
                "elastic step"
            );
            assert!(
                state.damage > before.damage && state.damage < 1.0,
                "D {}",
                state.damage
            );
            assert!(state.eos_history < before.eos_history, "no compaction");
        }
        bencher
            .counter(ItemsCount::new(SHORT_BLOCK))
            .bench_local(|| {
                let material = black_box(&material);
                let mut state = black_box(start);
                for _ in 0..SHORT_BLOCK {
                    let input = uniaxial_step(PLASTIC_AXIAL, PLASTIC_DT, state.relative_volume);
                    rht::update(material, &mut state, black_box(&input)).expect("update failed");
                }
                state
            });
    }
}

/// K&C concrete updates per second ([`KcMaterial::HPC_100MPA_FOI`] with the crack band of a
/// 10 mm element, `stoss_kernel::kc::update`), uniaxial compressive strain as for RHT.
mod kc {
    use super::*;
    use stoss_kernel::kc::{self, KcMaterial, KcParameters};

    fn material() -> KcMaterial {
        let material = KcMaterial {
            parameters: KcParameters::HPC_100MPA_FOI.with_fracture_energy(156.0, 0.01),
            ..KcMaterial::HPC_100MPA_FOI
        };
        material.validate().expect("invalid benchmark material");
        material
    }

    fn step(material: &KcMaterial, state: &mut MaterialState, axial: f64, dt: f64) -> bool {
        let input = uniaxial_step(axial, dt, state.relative_volume);
        kc::update(material, state, &input).expect("K&C update failed");
        state.flags.0 & StateFlags::PLASTIC != 0
    }

    /// [`BLOCK`] consecutive updates of `deps_xx = -1e-9` from the virgin state (far inside
    /// the yield surface; asserted).
    #[divan::bench]
    fn elastic(bencher: Bencher) {
        let material = material();
        let start = material.initial_state(ROOM_TEMPERATURE);
        let mut state = start;
        for _ in 0..BLOCK {
            assert!(
                !step(&material, &mut state, -1.0e-9, 1.0e-8),
                "elastic block yielded"
            );
        }
        bencher.counter(ItemsCount::new(BLOCK)).bench_local(|| {
            let material = black_box(&material);
            let mut state = black_box(start);
            for _ in 0..BLOCK {
                let input = uniaxial_step(-1.0e-9, 1.0e-8, state.relative_volume);
                kc::update(material, &mut state, black_box(&input)).expect("update failed");
            }
            state
        });
    }

    /// [`BLOCK`] consecutive plastic-loading updates past the peak of the damage function
    /// (softening towards the residual surface; every step plastic, asserted).
    #[divan::bench]
    fn softening_path(bencher: Bencher) {
        let material = material();
        let peak = material.parameters.damage.peak_lambda();
        let mut start = material.initial_state(ROOM_TEMPERATURE);
        let mut steps = 0;
        while start.plastic_strain <= peak {
            step(&material, &mut start, PLASTIC_AXIAL, PLASTIC_DT);
            steps += 1;
            assert!(steps < 100 * BLOCK, "never past the peak");
        }
        let mut state = start;
        for _ in 0..BLOCK {
            assert!(
                step(&material, &mut state, PLASTIC_AXIAL, PLASTIC_DT),
                "elastic step"
            );
        }
        bencher.counter(ItemsCount::new(BLOCK)).bench_local(|| {
            let material = black_box(&material);
            let mut state = black_box(start);
            for _ in 0..BLOCK {
                let input = uniaxial_step(PLASTIC_AXIAL, PLASTIC_DT, state.relative_volume);
                kc::update(material, &mut state, black_box(&input)).expect("update failed");
            }
            state
        });
    }
}

/// The kernel's own `exp`, `ln` and `pow` against the `libm` crate's: [`BLOCK`] independent
/// calls per iteration (throughput) over arguments of the kernel's ranges (plastic strains to
/// hardening exponents, rate ratios, Voce decays).
mod math {
    use super::*;

    fn arguments() -> Vec<f64> {
        (0..BLOCK).map(|i| 1e-4 + f64::from(i) * 1.3e-3).collect()
    }

    /// The sum of `function` over `arguments`, one block per iteration (generic, so that the
    /// function is inlined as in the kernel).
    fn bench_calls(bencher: Bencher, arguments: Vec<f64>, function: impl Fn(f64) -> f64) {
        bencher.counter(ItemsCount::new(BLOCK)).bench_local(|| {
            black_box(&arguments)
                .iter()
                .map(|&x| function(x))
                .sum::<f64>()
        });
    }

    #[divan::bench(args = ["stoss", "libm"])]
    fn pow(bencher: Bencher, which: &str) {
        match which {
            "stoss" => bench_calls(bencher, arguments(), |x| stoss_kernel::math::pow(x, 0.26)),
            _ => bench_calls(bencher, arguments(), |x| libm::pow(x, 0.26)),
        }
    }

    #[divan::bench(args = ["stoss", "libm"])]
    fn ln(bencher: Bencher, which: &str) {
        let xs: Vec<f64> = arguments().iter().map(|x| 1.0 + 1e5 * x).collect();
        match which {
            "stoss" => bench_calls(bencher, xs, stoss_kernel::math::ln),
            _ => bench_calls(bencher, xs, libm::log),
        }
    }

    #[divan::bench(args = ["stoss", "libm"])]
    fn exp(bencher: Bencher, which: &str) {
        let xs: Vec<f64> = arguments().iter().map(|x| -20.0 * x).collect();
        match which {
            "stoss" => bench_calls(bencher, xs, stoss_kernel::math::exp),
            _ => bench_calls(bencher, xs, libm::exp),
        }
    }
}

fn main() {
    if std::env::args().any(|a| a == "--alternate") {
        alternate();
        return;
    }
    divan::main();
}

/// `--alternate`: the [`block`] case one point at a time and through [`update_block`],
/// alternated sample by sample in one process, so that both see the same machine (on a
/// shared core the speed of either changes by a third from one second to the next); prints
/// the 10th and 50th percentiles of ns per update over [`ALTERNATE_SAMPLES`] samples each.
fn alternate() {
    let models: [(&str, Material); 4] = [
        ("jc_4340", jc()),
        ("za_bcc", za_bcc()),
        ("mjc", mjc()),
        ("tjc", tjc()),
    ];
    println!("model     one point at a time (p10 / p50)   grouped (p10 / p50)   ns per update");
    for (name, material) in models {
        let start = block_start(&material);
        let loadings: Vec<Loading> = (0..POINTS)
            .map(|point| Loading::new(block_axial(point), PLASTIC_DT))
            .collect();
        let mut inputs = vec![uniaxial_step(0.0, PLASTIC_DT, 1.0); POINTS];
        let mut results = vec![Err(UpdateError::NonFiniteInput); POINTS];
        let mut times = [Vec::new(), Vec::new()];
        for sample in 0..2 * ALTERNATE_SAMPLES {
            let grouped = sample % 2 == 1;
            let mut states = start.clone();
            let clock = std::time::Instant::now();
            for _ in 0..BLOCK_STEPS {
                for ((input, state), loading) in inputs.iter_mut().zip(&states).zip(&loadings) {
                    *input = loading.step(state.relative_volume);
                }
                if grouped {
                    update_block(black_box(&material), &mut states, &inputs, &mut results);
                } else {
                    for ((state, input), result) in
                        states.iter_mut().zip(&inputs).zip(results.iter_mut())
                    {
                        *result = update(black_box(&material), state, input);
                    }
                }
            }
            let per_update =
                clock.elapsed().as_secs_f64() * 1e9 / (BLOCK_STEPS as usize * POINTS) as f64;
            times[usize::from(grouped)].push(per_update);
            black_box(&states);
        }
        let [mut one, mut group] = times;
        let percentile = |v: &mut Vec<f64>, q: f64| {
            v.sort_by(f64::total_cmp);
            v[(q * (v.len() - 1) as f64) as usize]
        };
        println!(
            "{name:9} {:8.1} / {:8.1}                {:8.1} / {:8.1}",
            percentile(&mut one, 0.1),
            percentile(&mut one, 0.5),
            percentile(&mut group, 0.1),
            percentile(&mut group, 0.5)
        );
    }
}

/// Samples of each way in `--alternate`.
const ALTERNATE_SAMPLES: usize = 1500;
