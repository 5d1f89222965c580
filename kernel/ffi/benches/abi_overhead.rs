//! Cost of the C ABI per integration point against a direct Rust call of the kernel.
//!
//! Every benchmark updates `n` points by one step from the same developed plastic state of
//! JC 4340 (implicit return, uniaxial compressive strain `deps_xx = -1e-5` in `dt = 1e-8 s`,
//! as the kernel's `updates` benchmark): the step is a plastic return for every point. The
//! states are reset outside the timed region (divan `with_inputs`).
//!
//! - `direct`: `stoss_kernel::update` on an array of `MaterialState` (array of structs);
//! - `direct_grouped`: `stoss_kernel::update_block` on the same array, 8 points at a time (the
//!   group update the batch uses when no tangent is asked for);
//! - `batch`: `stoss_update_batch` on structure-of-arrays storage (validates the block,
//!   converts it to a kernel `Material`, checks every pointer, reads and writes every field
//!   through the panic boundary);
//! - `umat`: `stoss_lsdyna_umat` (also parses the card on every call);
//! - `vumat`: `stoss_abaqus_vumat` (also parses the props card on every call).
//!
//! The overhead per point is `(t_abi - t_direct) / n`; with `n = 1` it is the fixed cost of a
//! call. Run with `cargo bench -p stoss-kernel-ffi --bench abi_overhead`.

use std::ptr::{null, null_mut};

use divan::counter::ItemsCount;
use divan::{black_box, Bencher};
use stoss_kernel::{update, update_block, Material, MaterialState, StepInput, UpdateError};
use stoss_kernel_ffi::card::STOSS_CARD_MAX_LENGTH;
use stoss_kernel_ffi::*;

const POINTS: [usize; 4] = [1, 16, 128, 1024];
const INCREMENT: f64 = -1e-5;
const DT: f64 = 1e-8;

fn main() {
    if std::env::args().any(|a| a == "--alternate") {
        alternate();
        return;
    }
    divan::main();
}

/// Samples of each way in `--alternate`.
const ALTERNATE_SAMPLES: usize = 2000;

/// `--alternate`: `stoss_update_batch` against the direct `update_block` call it makes (and
/// the direct one-point loop), 128 and 1024 points, alternated sample by sample in one process
/// so that every way sees the same machine (a shared core changes speed by a third from one
/// second to the next). The batch runs twice: with the end-of-step relative volumes given (the
/// same input the direct calls get) and integrating them itself (`V0 exp(tr deps)`, one `exp`
/// per point that the direct calls do not do). Prints the 10th and 50th percentiles of ns per
/// point and each batch's overhead over the direct group call.
fn alternate() {
    let block = StossMaterialBlock::steel_4340();
    let material = block.to_material().expect("material");
    let base = plastic_state(&material);
    let step = next_step(&base);
    println!("ns per point, p10 / p50; overhead over the direct group call at p10 and p50");
    println!("points   direct one point   direct grouped   batch, volumes given     batch, volumes integrated");
    for n in [128, 1024] {
        let soas = [
            Soa::new(&base, n).with_given_volume(&base),
            Soa::new(&base, n),
        ];
        let inputs = vec![step; n];
        let mut results = vec![Err(UpdateError::NonFiniteInput); n];
        let mut times = [Vec::new(), Vec::new(), Vec::new(), Vec::new()];
        for sample in 0..4 * ALTERNATE_SAMPLES {
            let way = sample % 4;
            let mut states = vec![base; n];
            let mut batch = soas[way % 2].clone();
            let clock = std::time::Instant::now();
            match way {
                0 => {
                    for (state, result) in states.iter_mut().zip(results.iter_mut()) {
                        *result = update(black_box(&material), state, black_box(&step));
                    }
                }
                1 => {
                    update_block(black_box(&material), &mut states, &inputs, &mut results);
                }
                _ => {
                    assert_eq!(batch.run(black_box(&block)), StossStatus::Ok);
                }
            }
            times[way].push(clock.elapsed().as_secs_f64() * 1e9 / n as f64);
            black_box((&states, &results, &batch));
        }
        let [one, grouped, given, integrated] = times.map(|mut v| {
            v.sort_by(f64::total_cmp);
            [v[v.len() / 10], v[v.len() / 2]]
        });
        let overhead = |t: [f64; 2]| {
            format!(
                "{:6.1} / {:6.1} ({:+.1} %, {:+.1} %)",
                t[0],
                t[1],
                100.0 * (t[0] / grouped[0] - 1.0),
                100.0 * (t[1] / grouped[1] - 1.0)
            )
        };
        println!(
            "{n:6}   {:6.1} / {:6.1}    {:6.1} / {:6.1}   {}   {}",
            one[0],
            one[1],
            grouped[0],
            grouped[1],
            overhead(given),
            overhead(integrated),
        );
    }
}

fn input() -> StepInput {
    StepInput {
        strain_increment: [INCREMENT, 0.0, 0.0, 0.0, 0.0, 0.0],
        dt: DT,
        relative_volume: 1.0,
    }
}

/// The step from `state` (a plastic one from [`plastic_state`]), its end volume given.
fn next_step(state: &MaterialState) -> StepInput {
    StepInput {
        relative_volume: state.relative_volume * stoss_kernel::math::exp(INCREMENT),
        ..input()
    }
}

/// A state in developed plastic flow whose next step is a plastic return.
fn plastic_state(material: &Material) -> MaterialState {
    let mut state = MaterialState::initial(298.0);
    let mut plastic_steps = 0;
    while plastic_steps < 50 {
        let mut step = input();
        step.relative_volume =
            state.relative_volume * stoss_kernel::math::exp(step.strain_increment[0]);
        let output = update(material, &mut state, &step).expect("preload");
        if output.plastic_increment > 0.0 {
            plastic_steps += 1;
        }
    }
    state
}

#[derive(Clone)]
struct Soa {
    n: usize,
    strain: [Vec<f64>; 6],
    stress: [Vec<f64>; 6],
    scalars: [Vec<f64>; 7],
    flags: Vec<u32>,
    wave_speed: Vec<f64>,
    status: Vec<i32>,
    /// End-of-step relative volumes, if the host gives them (else the batch integrates
    /// `V0 exp(tr deps)` itself).
    given_volume: Vec<f64>,
}

impl Soa {
    fn new(state: &MaterialState, n: usize) -> Self {
        let scalars = [
            state.plastic_strain,
            state.plastic_strain_rate,
            state.temperature,
            state.damage,
            state.relative_volume,
            state.internal_energy,
            state.eos_history,
        ];
        Self {
            n,
            strain: std::array::from_fn(|k| vec![if k == 0 { INCREMENT } else { 0.0 }; n]),
            stress: std::array::from_fn(|k| vec![state.stress[k]; n]),
            scalars: std::array::from_fn(|k| vec![scalars[k]; n]),
            flags: vec![state.flags.0; n],
            wave_speed: vec![0.0; n],
            status: vec![0; n],
            given_volume: Vec::new(),
        }
    }

    /// The same batch with the end-of-step relative volumes given, as the direct call is.
    fn with_given_volume(mut self, state: &MaterialState) -> Self {
        self.given_volume =
            vec![state.relative_volume * stoss_kernel::math::exp(INCREMENT); self.n];
        self
    }

    fn run(&mut self, block: &StossMaterialBlock) -> StossStatus {
        let input = StossBatchInput {
            strain_increment: std::array::from_fn(|k| self.strain[k].as_ptr()),
            relative_volume: if self.given_volume.is_empty() {
                null()
            } else {
                self.given_volume.as_ptr()
            },
        };
        let [eps, rate, t, d, v, e, h] = &mut self.scalars;
        let mut stress = [null_mut(); 6];
        for (k, array) in self.stress.iter_mut().enumerate() {
            stress[k] = array.as_mut_ptr();
        }
        let state = StossBatchState {
            stress,
            plastic_strain: eps.as_mut_ptr(),
            plastic_strain_rate: rate.as_mut_ptr(),
            temperature: t.as_mut_ptr(),
            damage: d.as_mut_ptr(),
            relative_volume: v.as_mut_ptr(),
            internal_energy: e.as_mut_ptr(),
            eos_history: h.as_mut_ptr(),
            flags: self.flags.as_mut_ptr(),
        };
        let output = StossBatchOutput {
            wave_speed: self.wave_speed.as_mut_ptr(),
            failed: null_mut(),
            status: self.status.as_mut_ptr(),
            tangent: null_mut(),
        };
        // SAFETY: every array holds `n` elements.
        unsafe {
            stoss_update_batch(
                block,
                self.n,
                DT,
                &input,
                &state,
                &output,
                null_mut(),
                null_mut(),
                0,
            )
        }
    }
}

/// Column-major LS-DYNA / Abaqus arrays for `n` points.
#[derive(Clone)]
struct Fortran {
    n: usize,
    strain: Vec<f64>,
    stress: Vec<f64>,
    stress_new: Vec<f64>,
    history: Vec<f64>,
    history_new: Vec<f64>,
    energy: Vec<f64>,
    energy_new: Vec<f64>,
    wave_speed: Vec<f64>,
}

impl Fortran {
    fn new(state: &MaterialState, n: usize) -> Self {
        let mut strain = vec![0.0; 6 * n];
        let mut stress = vec![0.0; 6 * n];
        let mut history = vec![0.0; STOSS_HISTORY_COUNT * n];
        let values = stoss_kernel_ffi::adapters::history_from_state(state);
        for i in 0..n {
            strain[i] = INCREMENT;
            for k in 0..6 {
                stress[i + n * k] = state.stress[k];
            }
            for (j, value) in values.iter().enumerate() {
                history[i + n * j] = *value;
            }
        }
        Self {
            n,
            strain,
            stress_new: stress.clone(),
            stress,
            history_new: history.clone(),
            history,
            energy: vec![0.0; n],
            energy_new: vec![0.0; n],
            wave_speed: vec![0.0; n],
        }
    }
}

fn card(block: &StossMaterialBlock) -> Vec<f64> {
    let mut card = vec![0.0; STOSS_CARD_MAX_LENGTH];
    let mut length = 0;
    // SAFETY: `card` holds STOSS_CARD_MAX_LENGTH doubles.
    let status = unsafe {
        stoss_material_to_card(
            block,
            card.as_mut_ptr(),
            card.len(),
            &mut length,
            null_mut(),
            0,
        )
    };
    assert_eq!(status, StossStatus::Ok);
    card.truncate(length);
    card
}

#[divan::bench(args = POINTS)]
fn direct(bencher: Bencher, n: usize) {
    let material = Material::STEEL_4340;
    let base = plastic_state(&material);
    let step = next_step(&base);
    bencher
        .counter(ItemsCount::new(n))
        .with_inputs(|| vec![base; n])
        .bench_local_refs(|states| {
            for state in states.iter_mut() {
                let output = update(black_box(&material), state, black_box(&step));
                assert!(output.expect("plastic step").plastic_increment > 0.0);
            }
        });
}

/// `stoss_kernel::update_block` on an array of `MaterialState`: the direct call of the group
/// update that `stoss_update_batch` makes (without a tangent), the reference of its overhead.
#[divan::bench(args = POINTS)]
fn direct_grouped(bencher: Bencher, n: usize) {
    let material = Material::STEEL_4340;
    let base = plastic_state(&material);
    let step = next_step(&base);
    let inputs = vec![step; n];
    bencher
        .counter(ItemsCount::new(n))
        .with_inputs(|| (vec![base; n], vec![Err(UpdateError::NonFiniteInput); n]))
        .bench_local_refs(|(states, results)| {
            update_block(black_box(&material), states, black_box(&inputs), results);
            for output in results.iter() {
                assert!(output.as_ref().expect("plastic step").plastic_increment > 0.0);
            }
        });
}

/// `stoss_update_batch` over `n` points from the plastic state, the relative volumes given
/// or integrated by the batch.
fn bench_batch(bencher: Bencher, n: usize, given_volume: bool) {
    let block = StossMaterialBlock::steel_4340();
    let base = plastic_state(&block.to_material().unwrap());
    let soa = if given_volume {
        Soa::new(&base, n).with_given_volume(&base)
    } else {
        Soa::new(&base, n)
    };
    bencher
        .counter(ItemsCount::new(n))
        .with_inputs(|| soa.clone())
        .bench_local_refs(|soa| {
            let status = soa.run(black_box(&block));
            assert_eq!(status, StossStatus::Ok);
        });
}

#[divan::bench(args = POINTS)]
fn batch(bencher: Bencher, n: usize) {
    bench_batch(bencher, n, false);
}

#[divan::bench(args = POINTS)]
fn batch_given_volume(bencher: Bencher, n: usize) {
    bench_batch(bencher, n, true);
}

#[divan::bench(args = POINTS)]
fn umat(bencher: Bencher, n: usize) {
    let block = StossMaterialBlock::steel_4340();
    let base = plastic_state(&block.to_material().unwrap());
    let cm = card(&block);
    let arrays = Fortran::new(&base, n);
    bencher
        .counter(ItemsCount::new(n))
        .with_inputs(|| arrays.clone())
        .bench_local_refs(|a| {
            // SAFETY: arrays sized for `n` points, 6 components, 8 history values.
            let status = unsafe {
                stoss_lsdyna_umat(
                    black_box(cm.as_ptr()),
                    cm.len(),
                    a.n,
                    DT,
                    a.strain.as_ptr(),
                    a.stress.as_mut_ptr(),
                    a.history.as_mut_ptr(),
                    STOSS_HISTORY_COUNT,
                    null_mut(),
                    a.wave_speed.as_mut_ptr(),
                    null_mut(),
                    null_mut(),
                    null_mut(),
                    0,
                )
            };
            assert_eq!(status, StossStatus::Ok);
        });
}

#[divan::bench(args = POINTS)]
fn vumat(bencher: Bencher, n: usize) {
    let block = StossMaterialBlock::steel_4340();
    let base = plastic_state(&block.to_material().unwrap());
    let props = card(&block);
    let arrays = Fortran::new(&base, n);
    bencher
        .counter(ItemsCount::new(n))
        .with_inputs(|| arrays.clone())
        .bench_local_refs(|a| {
            // SAFETY: arrays sized for `n` points, 6 components, 8 state variables.
            let status = unsafe {
                stoss_abaqus_vumat(
                    black_box(props.as_ptr()),
                    props.len(),
                    a.n,
                    3,
                    3,
                    STOSS_HISTORY_COUNT,
                    1e-3,
                    1e-3,
                    DT,
                    a.strain.as_ptr(),
                    a.stress.as_ptr(),
                    a.history.as_ptr(),
                    a.energy.as_ptr(),
                    a.stress_new.as_mut_ptr(),
                    a.history_new.as_mut_ptr(),
                    a.energy_new.as_mut_ptr(),
                    a.wave_speed.as_mut_ptr(),
                    null_mut(),
                    null_mut(),
                    null_mut(),
                    0,
                )
            };
            assert_eq!(status, StossStatus::Ok);
        });
}
