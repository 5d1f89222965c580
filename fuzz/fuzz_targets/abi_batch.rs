//! The C ABI entry: fuzzed material blocks (corrupted headers, invalid constants and
//! selectors), point counts, time steps, strain increments, states, message capacities and
//! pointer mistakes (NULL, misaligned) through the real `extern "C"` exports
//! `stoss_update_batch` (three inputs in four) and `stoss_lsdyna_umat` (card form, the
//! rest), called through the safe wrappers of `stoss_kernel_ffi::checked`: this crate has no
//! `unsafe` code.
//!
//! Properties (fuzz/README.md, "abi_batch"):
//! - no panic, and no `STOSS_STATUS_PANIC`; every status (returned and per point) is one of
//!   the documented codes;
//! - call-level checks in their documented order: NULL/misaligned block, layout version,
//!   struct size, constants, `n = 0`, then the input, state and output pointers (NULL where
//!   required -> `NULL_POINTER`, misaligned -> `MISALIGNED_POINTER`); the message names the
//!   offending argument; nothing is written on a call-level error;
//! - otherwise every point gives, bit for bit, what the Rust functions the ABI documents as
//!   its equivalent give (`step_point`, `lsdyna_umat_point`): state, wave speed, failure code,
//!   per-point status, tangent; a failing point keeps its input state bit for bit; the
//!   return value and `first_failure` are those of the first failing point (`OK`, `n` if
//!   none); points and output slots at or beyond `n` are never touched;
//! - `OK` points had finite inputs and give a finite state, stress and wave speed;
//! - a NaN/inf strain component gives `NON_FINITE_INPUT` at its point; a negative `dt` gives
//!   `NON_POSITIVE_TIME_STEP` at every point with finite inputs;
//! - the message is NUL-terminated within its capacity, UTF-8, the documented text truncated
//!   at a character boundary, the empty string on success; a capacity of 0 and the guard
//!   bytes after the capacity are never written.
#![no_main]
#![forbid(unsafe_code)]

use stoss_fuzz::check::state_bits;
use stoss_fuzz::source::Source;
use stoss_kernel::eos::TabulatedCompaction;
use stoss_kernel::strength::ZerilliArmstrong;
use stoss_kernel::{MaterialState, StateFlags, UpdateError};
use stoss_kernel_ffi::adapters::{history_from_state, STOSS_HISTORY_COUNT};
use stoss_kernel_ffi::batch::failure_code;
use stoss_kernel_ffi::block::{
    StossEosModel, StossHeatingModel, StossRateTreatment, StossStrengthModel,
};
use stoss_kernel_ffi::card::STOSS_CARD_MAX_LENGTH;
use stoss_kernel_ffi::checked::{
    lsdyna_umat, update_batch, BatchCall, BatchPointers, BatchStateData, CallOutcome, Message,
    Pass, UmatCall, UmatPointers,
};
use stoss_kernel_ffi::{
    block_from_card, card_from_block, lsdyna_umat_point, step_point, StossMaterialBlock,
    StossStatus, STOSS_LAYOUT_VERSION,
};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    run(data);
});

/// Sentinels of the output arrays: any change means the ABI wrote the slot.
const WAVE_SENTINEL: f64 = -12345.678;
const CODE_SENTINEL: i32 = -777;
const TANGENT_SENTINEL: f64 = -9.87e300;

/// Per-point statuses (what `output->status` may hold besides `OK`).
const POINT_STATUSES: [StossStatus; 8] = [
    StossStatus::Ok,
    StossStatus::NonFiniteInput,
    StossStatus::NonPositiveTimeStep,
    StossStatus::NonPositiveVolume,
    StossStatus::ReturnMappingDiverged,
    StossStatus::NonFiniteState,
    StossStatus::NonFiniteResult,
    StossStatus::InadmissibleState,
];

const STRAIN_FIELDS: [&str; 6] = [
    "input.strain_increment[0] (xx)",
    "input.strain_increment[1] (yy)",
    "input.strain_increment[2] (zz)",
    "input.strain_increment[3] (xy)",
    "input.strain_increment[4] (yz)",
    "input.strain_increment[5] (zx)",
];
const STATE_FIELDS: [&str; 14] = [
    "state.stress[0] (xx)",
    "state.stress[1] (yy)",
    "state.stress[2] (zz)",
    "state.stress[3] (xy)",
    "state.stress[4] (yz)",
    "state.stress[5] (zx)",
    "state.plastic_strain",
    "state.plastic_strain_rate",
    "state.temperature",
    "state.damage",
    "state.relative_volume",
    "state.internal_energy",
    "state.eos_history",
    "state.flags",
];

/// Values a host gets wrong: non-finite, zero, signs, huge, non-integer codes.
const SPECIALS: [f64; 12] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    0.0,
    -0.0,
    -1.0,
    1.5,
    2.0,
    1e300,
    -1e300,
    5e-324,
    f64::MAX,
];

fn run(data: &[u8]) {
    let mut src = Source::new(data);
    let mode = src.byte();
    let block = material(&mut src);
    if mode % 4 == 3 {
        umat(&mut src, block);
    } else {
        batch(&mut src, block);
    }
}

// ---------------------------------------------------------------------------------------------
// Inputs

fn special(src: &mut Source) -> f64 {
    SPECIALS[usize::from(src.byte()) % SPECIALS.len()]
}

fn pass(src: &mut Source) -> Pass {
    if src.flag() {
        Pass::Misaligned
    } else {
        Pass::Null
    }
}

/// A material block: one of six families of presets, constants perturbed (outside their
/// domain in the chaotic regime), and now and then a corrupted header, selector or switch.
fn material(src: &mut Source) -> StossMaterialBlock {
    let mut block = StossMaterialBlock::steel_4340();
    block.density = src.linear(2000.0, 20000.0);
    block.shear_modulus = src.log(1e9, 3e11);
    block.strength.johnson_cook.yield_stress = src.log(1e7, 3e9);
    block.strength.johnson_cook.hardening_modulus = src.linear(0.0, 2e9);
    block.initial_temperature = src.linear(200.0, 1000.0);
    match src.choice(6) {
        0 => {}
        1 => {
            let f = &mut block.failure;
            f.johnson_cook_enabled = 1;
            f.erode_on_failure = u32::from(src.flag());
            f.erosion_enabled = u32::from(src.flag());
            f.erosion_plastic_strain = src.linear(0.01, 2.0);
            f.pressure_cutoff_enabled = u32::from(src.flag());
            f.pressure_cutoff = src.linear(-5e9, 0.0);
        }
        2 => {
            block.eos_model = StossEosModel::MieGruneisen as i32;
            let m = &mut block.eos.mie_gruneisen;
            m.reference_density = block.density;
            m.sound_speed = src.linear(3000.0, 6000.0);
            m.s1 = src.linear(1.0, 2.0);
            m.gamma0 = src.linear(1.0, 2.5);
            block.rate_treatment = StossRateTreatment::Lagged as i32;
        }
        3 => {
            block.strength_model = if src.flag() {
                StossStrengthModel::ZerilliArmstrongFcc as i32
            } else {
                StossStrengthModel::ZerilliArmstrongBcc as i32
            };
            block.heating_model = StossHeatingModel::Isothermal as i32;
            let za = &mut block.strength.zerilli_armstrong;
            let mut values = [0.0; 6];
            let names = ["athermal_stress", "c1", "c3", "c4", "c5", "exponent"];
            for (value, name) in values.iter_mut().zip(names) {
                let (min, max) = ZerilliArmstrong::PARAMETERS
                    .iter()
                    .find(|p| p.name == name)
                    .and_then(|p| p.search)
                    .expect("ZA search range");
                *value = src.linear(min, max);
            }
            [za.athermal_stress, za.c1, za.c3, za.c4, za.c5, za.exponent] = values;
            za.c2 = src.linear(0.0, 3.0e9);
            za.reference_rate = src.log(1e-3, 1e3);
        }
        4 => {
            block.eos_model = StossEosModel::PAlpha as i32;
            let p = &mut block.eos.p_alpha;
            p.solid.a1 = 159.0e9;
            p.solid.t1 = 159.0e9;
            p.solid.b0 = 1.5;
            p.initial_distension = src.linear(1.01, 1.5);
            p.crush_pressure = src.log(1e6, 1e8);
            p.lock_pressure = src.log(1e9, 5e9);
            p.exponent = src.linear(1.0, 4.0);
            block.heating_model = StossHeatingModel::Transition as i32;
            block.heating.isothermal_rate = src.log(1e-2, 1e2);
            block.heating.adiabatic_rate = block.heating.isothermal_rate * src.log(2.0, 1e4);
        }
        _ => {
            block.eos_model = StossEosModel::TabulatedCompaction as i32;
            let table = TabulatedCompaction::CONCRETE_FOI_TABLE_5_2;
            let t = &mut block.eos.tabulated_compaction;
            t.point_count = table.points().len() as u32;
            for (i, point) in table.points().iter().enumerate() {
                t.volumetric_strain[i] = point.volumetric_strain;
                t.pressure[i] = point.pressure;
                t.unloading_bulk_modulus[i] = point.unloading_bulk_modulus;
            }
        }
    }
    // Corruptions (a zero byte, the end of the input, means none).
    match src.byte() {
        250 => block.layout_version = u32::from(src.byte()),
        251 => block.struct_size = u32::from(src.byte()) << src.choice(24),
        252 => block.strength_model = i32::from(src.byte() as i8),
        253 => block.eos_model = i32::from(src.byte() as i8),
        254 => block.failure.erosion_enabled = u32::from(src.byte()),
        255 => block.density = special(src),
        _ => {}
    }
    block
}

/// A point state: the material's initial state, or a perturbed one (outside its domain in
/// the chaotic regime, or with a special value or stray flags now and then).
fn point_state(src: &mut Source, initial: &MaterialState) -> MaterialState {
    let mut state = *initial;
    if src.byte() < 128 {
        return state;
    }
    for s in state.stress.iter_mut() {
        *s = src.linear(-3e9, 3e9);
    }
    state.plastic_strain = src.zero_or_log(1e-8, 2.0);
    state.plastic_strain_rate = src.zero_or_log(1e-6, 1e6);
    state.temperature = src.linear(200.0, 1500.0);
    state.damage = src.linear(0.0, 1.0);
    state.relative_volume = src.linear(0.7, 1.3);
    state.internal_energy = src.linear(-1e9, 1e9);
    match src.byte() {
        240..=247 => state.flags = StateFlags(u32::from(src.byte() & 15)),
        248..=251 => state.relative_volume = special(src),
        252..=255 => state.temperature = special(src),
        _ => {}
    }
    state
}

fn time_step(src: &mut Source) -> f64 {
    match src.byte() {
        240..=243 => -src.log(1e-9, 1e-3),
        244..=249 => special(src),
        _ => src.log(1e-9, 1e-3),
    }
}

/// Message capacity: mostly large, often tiny (truncation), sometimes NULL.
fn message_capacity(src: &mut Source) -> Option<usize> {
    match src.byte() {
        0..=127 => Some(256),
        128..=239 => Some(usize::from(src.byte() % 48)),
        240..=247 => None,
        _ => Some(1),
    }
}

fn initial_state_of(block: &StossMaterialBlock) -> MaterialState {
    match block.to_model() {
        Ok(model) => block.initial_state(&model),
        Err(_) => MaterialState::initial(298.0),
    }
}

// ---------------------------------------------------------------------------------------------
// Message

/// `full` cut to `capacity - 1` bytes at a character boundary (the documented truncation).
fn truncated(full: &str, capacity: usize) -> &str {
    let mut length = full.len().min(capacity.saturating_sub(1));
    while !full.is_char_boundary(length) {
        length -= 1;
    }
    &full[..length]
}

/// What the message must say: exactly a text, or something starting with an argument name.
enum Expected<'a> {
    Exact(&'a str),
    Field(&'a str),
}

fn check_message(message: &Option<Message>, status: StossStatus, expected: Expected<'_>) {
    let Some(message) = message else { return };
    assert!(
        message.guard_intact,
        "the ABI wrote past the message capacity {}",
        message.capacity
    );
    if message.capacity == 0 {
        assert!(
            message.untouched(),
            "a zero-capacity message buffer was written"
        );
        return;
    }
    let Some(text) = message.text() else {
        panic!(
            "message not NUL-terminated UTF-8 within its capacity {}: {:?}",
            message.capacity, message.bytes
        );
    };
    assert!(text.len() < message.capacity);
    match expected {
        Expected::Exact(full) => assert_eq!(
            text,
            truncated(full, message.capacity),
            "message (capacity {}), status {status:?}",
            message.capacity
        ),
        Expected::Field(field) => {
            assert!(
                text.starts_with(field) || field.starts_with(text),
                "message {text:?} does not name {field:?} (status {status:?})"
            );
            assert!(
                message.capacity < 2 || !text.is_empty(),
                "empty message with status {status:?}"
            );
        }
    }
}

fn check_status(status: StossStatus) {
    assert_ne!(
        status,
        StossStatus::Panic,
        "STOSS_STATUS_PANIC: a panic was caught at the boundary"
    );
    assert_eq!(StossStatus::from_code(status as i32), Some(status));
}

fn check_point_code(code: i32) {
    assert!(
        POINT_STATUSES.iter().any(|s| *s as i32 == code),
        "per-point status {code} is not a per-point status code"
    );
}

/// A call-level error: status and the argument or text the message must name.
struct CallError {
    status: StossStatus,
    field: String,
    exact: bool,
}

impl CallError {
    fn field(status: StossStatus, field: &str) -> Self {
        Self {
            status,
            field: field.to_owned(),
            exact: false,
        }
    }

    fn pointer(pass: Pass, field: &str, required: bool) -> Option<Self> {
        match pass {
            Pass::Valid => None,
            Pass::Null if required => Some(Self::field(StossStatus::NullPointer, field)),
            Pass::Null => None,
            Pass::Misaligned => Some(Self::field(StossStatus::MisalignedPointer, field)),
        }
    }

    fn check(&self, outcome: &CallOutcome) {
        assert_eq!(
            outcome.status, self.status,
            "call-level error: expected {:?} ({}), got {:?} {:?}",
            self.status, self.field, outcome.status, outcome.message
        );
        let expected = if self.exact {
            Expected::Exact(&self.field)
        } else {
            Expected::Field(&self.field)
        };
        check_message(&outcome.message, outcome.status, expected);
        if let Some(first) = outcome.first_failure {
            assert_eq!(
                first,
                CallOutcome::first_failure_unset(),
                "first_failure written by a call-level error"
            );
        }
    }
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

// ---------------------------------------------------------------------------------------------
// stoss_update_batch

fn batch(src: &mut Source, block: StossMaterialBlock) {
    // Up to 20 points: two groups of `LANES` (8) through the kernel's group update, and the
    // rest one at a time, when no tangent is asked for.
    let len = usize::from(src.count(1, 20));
    let n = match src.byte() % 8 {
        6 => usize::from(src.byte()) % (len + 1),
        7 => 0,
        _ => len,
    };
    let dt = time_step(src);
    let mut strain: [Vec<f64>; 6] = std::array::from_fn(|_| Vec::with_capacity(len));
    for _ in 0..len {
        for component in strain.iter_mut() {
            component.push(src.linear(-0.05, 0.05));
        }
    }
    // A non-finite strain component at one point.
    let poisoned = if src.byte() >= 224 {
        let i = usize::from(src.byte()) % len;
        let k = usize::from(src.choice(6));
        strain[k][i] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY][usize::from(src.choice(3))];
        Some(i)
    } else {
        None
    };
    let with_volume = src.flag();
    let relative_volume: Vec<f64> = (0..len)
        .map(|_| match src.byte() {
            252..=255 => special(src),
            _ => src.linear(0.6, 1.5),
        })
        .collect();
    let initial = initial_state_of(&block);
    let points: Vec<MaterialState> = (0..len).map(|_| point_state(src, &initial)).collect();

    let outputs = src.byte();
    let mut pointers = BatchPointers {
        relative_volume: if with_volume { Pass::Valid } else { Pass::Null },
        output: if outputs & 1 == 1 {
            Pass::Null
        } else {
            Pass::Valid
        },
        wave_speed: if outputs & 2 == 2 {
            Pass::Null
        } else {
            Pass::Valid
        },
        failed: if outputs & 4 == 4 {
            Pass::Null
        } else {
            Pass::Valid
        },
        status: if outputs & 8 == 8 {
            Pass::Null
        } else {
            Pass::Valid
        },
        tangent: if outputs & 16 == 16 {
            Pass::Valid
        } else {
            Pass::Null
        },
        ..BatchPointers::default()
    };
    // Up to two pointer mistakes among the 29 pointers.
    for _ in 0..2 {
        if src.byte() < 200 {
            continue;
        }
        let which = src.choice(29);
        let how = pass(src);
        match which {
            0 => pointers.block = how,
            1 => pointers.input = how,
            2..=7 => pointers.strain_increment[usize::from(which - 2)] = how,
            8 => pointers.relative_volume = how,
            9 => pointers.state = how,
            10..=23 => pointers.state_arrays[usize::from(which - 10)] = how,
            24 => pointers.output = how,
            25 => pointers.wave_speed = how,
            26 => pointers.failed = how,
            27 => pointers.status = how,
            _ => pointers.tangent = how,
        }
    }
    let first_failure = src.byte() & 1 == 0;
    let capacity = message_capacity(src);

    let mut call = BatchCall {
        block,
        n,
        dt,
        strain_increment: strain,
        relative_volume,
        state: BatchStateData::from_points(&points),
        wave_speed: vec![WAVE_SENTINEL; len],
        failed: vec![CODE_SENTINEL; len],
        status: vec![CODE_SENTINEL; len],
        tangent: vec![TANGENT_SENTINEL; 36 * len],
        first_failure,
        message_capacity: capacity,
        pointers,
    };
    let before = call.clone();
    let outcome = match update_batch(&mut call) {
        Ok(outcome) => outcome,
        Err(error) => panic!("harness: arrays shorter than n: {error}"),
    };
    check_status(outcome.status);
    check_batch(&before, &call, &outcome, poisoned);
}

/// The call-level error `stoss_update_batch` must report, in its documented order.
fn batch_call_error(call: &BatchCall) -> Option<CallError> {
    let p = &call.pointers;
    if let Some(error) = CallError::pointer(p.block, "block", true) {
        return Some(error);
    }
    let block = &call.block;
    if block.layout_version != STOSS_LAYOUT_VERSION {
        return Some(CallError::field(
            StossStatus::BadLayoutVersion,
            "layout_version",
        ));
    }
    if block.struct_size as usize != std::mem::size_of::<StossMaterialBlock>() {
        return Some(CallError::field(StossStatus::BadStructSize, "struct_size"));
    }
    if let Err(error) = block.to_model() {
        return Some(CallError {
            status: error.status,
            field: error.message,
            exact: true,
        });
    }
    if call.n == 0 {
        return Some(CallError::field(StossStatus::ZeroPoints, "n"));
    }
    let required = [(p.input, "input")]
        .into_iter()
        .chain(p.strain_increment.iter().copied().zip(STRAIN_FIELDS));
    for (pass, field) in required {
        if let Some(error) = CallError::pointer(pass, field, true) {
            return Some(error);
        }
    }
    if let Some(error) = CallError::pointer(p.relative_volume, "input.relative_volume", false) {
        return Some(error);
    }
    let required = [(p.state, "state")]
        .into_iter()
        .chain(p.state_arrays.iter().copied().zip(STATE_FIELDS));
    for (pass, field) in required {
        if let Some(error) = CallError::pointer(pass, field, true) {
            return Some(error);
        }
    }
    if p.output != Pass::Null {
        let optional = [
            (p.output, "output"),
            (p.wave_speed, "output.wave_speed"),
            (p.failed, "output.failed"),
            (p.status, "output.status"),
            (p.tangent, "output.tangent"),
        ];
        for (pass, field) in optional {
            if let Some(error) = CallError::pointer(pass, field, false) {
                return Some(error);
            }
        }
    }
    None
}

fn check_batch(
    before: &BatchCall,
    after: &BatchCall,
    outcome: &CallOutcome,
    poisoned: Option<usize>,
) {
    let n = before.n;
    let len = before.state.len();
    let p = &before.pointers;
    // Inputs are never written.
    for k in 0..6 {
        assert_eq!(
            bits(&before.strain_increment[k]),
            bits(&after.strain_increment[k]),
            "strain input {k} written"
        );
    }
    assert_eq!(bits(&before.relative_volume), bits(&after.relative_volume));

    // The headline properties, stated directly.
    if p.block == Pass::Null {
        assert_eq!(outcome.status, StossStatus::NullPointer, "NULL block");
    }
    if p.block == Pass::Valid && before.block.layout_version != STOSS_LAYOUT_VERSION {
        assert_eq!(
            outcome.status,
            StossStatus::BadLayoutVersion,
            "wrong layout version"
        );
    }
    if p.block == Pass::Valid && before.block.to_model().is_ok() && n == 0 {
        assert_eq!(outcome.status, StossStatus::ZeroPoints, "n = 0");
    }

    if let Some(error) = batch_call_error(before) {
        error.check(outcome);
        assert_state_unchanged(before, after, 0..len, "call-level error");
        assert_outputs_unchanged(before, after, 0..len);
        return;
    }

    let material = before
        .block
        .to_model()
        .expect("checked by batch_call_error");
    let outputs = p.output == Pass::Valid;
    let want = |pass: Pass| outputs && pass == Pass::Valid;
    let mut first: Option<(usize, UpdateError)> = None;
    for i in 0..n {
        let increment: [f64; 6] = std::array::from_fn(|k| before.strain_increment[k][i]);
        let volume = (p.relative_volume == Pass::Valid).then(|| before.relative_volume[i]);
        let state_in = before.state.point(i).expect("len >= n");
        let mut state = state_in;
        let mut matrix = [[0.0; 6]; 6];
        let result = step_point(
            &material,
            &mut state,
            &increment,
            before.dt,
            volume,
            want(p.tangent).then_some(&mut matrix),
        );
        let got = after.state.point(i).expect("len >= n");
        let observed = want(p.status).then(|| after.status[i]);
        if let Some(code) = observed {
            check_point_code(code);
        }
        let context = || {
            format!(
                "point {i} of {n}: increment {increment:?}, volume {volume:?}, dt {}, state \
                 {state_in:?}\nmaterial {material:?}",
                before.dt
            )
        };
        match result {
            Ok(step) => {
                assert_eq!(
                    state_bits(&got),
                    state_bits(&state),
                    "ABI state differs from step_point\n{}",
                    context()
                );
                // OK => finite in, finite out.
                assert!(
                    increment.iter().all(|e| e.is_finite())
                        && before.dt.is_finite()
                        && before.dt > 0.0
                        && state_in.is_finite(),
                    "OK from non-finite input\n{}",
                    context()
                );
                assert!(
                    got.is_finite() && step.wave_speed.is_finite(),
                    "OK with a non-finite state or wave speed {got:?} {step:?}\n{}",
                    context()
                );
                if let Some(code) = observed {
                    assert_eq!(code, StossStatus::Ok as i32, "{}", context());
                }
                if want(p.wave_speed) {
                    assert_eq!(after.wave_speed[i].to_bits(), step.wave_speed.to_bits());
                    assert!(after.wave_speed[i].is_finite());
                }
                if want(p.failed) {
                    assert_eq!(after.failed[i], failure_code(&state));
                }
                if want(p.tangent) {
                    let expected: Vec<f64> = matrix.iter().flatten().copied().collect();
                    assert_eq!(bits(&after.tangent[36 * i..36 * i + 36]), bits(&expected));
                }
            }
            Err(error) => {
                assert_eq!(
                    state_bits(&got),
                    state_bits(&state_in),
                    "failing point ({error:?}) changed its state\n{}",
                    context()
                );
                if let Some(code) = observed {
                    assert_eq!(code, StossStatus::from(error) as i32, "{}", context());
                }
                if want(p.wave_speed) {
                    assert_eq!(after.wave_speed[i].to_bits(), WAVE_SENTINEL.to_bits());
                }
                if want(p.failed) {
                    assert_eq!(after.failed[i], CODE_SENTINEL);
                }
                if want(p.tangent) {
                    assert!(after.tangent[36 * i..36 * i + 36]
                        .iter()
                        .all(|t| t.to_bits() == TANGENT_SENTINEL.to_bits()));
                }
                first.get_or_insert((i, error));
            }
        }
        // NaN/inf strain -> NON_FINITE_INPUT at that point.
        if poisoned == Some(i) {
            assert_eq!(
                result.err(),
                Some(UpdateError::NonFiniteInput),
                "{}",
                context()
            );
            if let Some(code) = observed {
                assert_eq!(code, StossStatus::NonFiniteInput as i32);
            }
        }
        // Negative dt -> NON_POSITIVE_TIME_STEP at every point with finite inputs (an
        // integrated volume V0 exp(tr deps) is finite for |deps_i| <= 1, |V0| <= 1e300).
        let finite_inputs = increment.iter().all(|e| e.is_finite() && e.abs() <= 1.0)
            && match volume {
                Some(volume) => volume.is_finite(),
                None => state_in.relative_volume.abs() <= 1e300,
            };
        if before.dt.is_finite() && before.dt < 0.0 && finite_inputs {
            assert_eq!(
                result.err(),
                Some(UpdateError::NonPositiveTimeStep),
                "{}",
                context()
            );
            if let Some(code) = observed {
                assert_eq!(code, StossStatus::NonPositiveTimeStep as i32);
            }
        }
    }
    // Points and output slots at or beyond n: untouched.
    assert_state_unchanged(before, after, n..len, "beyond n");
    assert_outputs_unchanged(before, after, n..len);

    match first {
        None => {
            assert_eq!(outcome.status, StossStatus::Ok);
            if let Some(index) = outcome.first_failure {
                assert_eq!(
                    index, n,
                    "first_failure must be n when every point succeeded"
                );
            }
            check_message(&outcome.message, outcome.status, Expected::Exact(""));
        }
        Some((index, error)) => {
            assert_eq!(
                outcome.status,
                StossStatus::from(error),
                "first failure {index}"
            );
            if let Some(reported) = outcome.first_failure {
                assert_eq!(reported, index);
            }
            let full = format!("point {index}: {error}");
            check_message(&outcome.message, outcome.status, Expected::Exact(&full));
        }
    }
}

fn assert_state_unchanged(
    before: &BatchCall,
    after: &BatchCall,
    range: std::ops::Range<usize>,
    what: &str,
) {
    assert_eq!(after.state.len(), before.state.len());
    for i in range {
        let (a, b) = (before.state.point(i), after.state.point(i));
        assert_eq!(
            a.map(|s| state_bits(&s)),
            b.map(|s| state_bits(&s)),
            "{what}: state of point {i} changed"
        );
    }
}

fn assert_outputs_unchanged(before: &BatchCall, after: &BatchCall, range: std::ops::Range<usize>) {
    for i in range {
        assert_eq!(
            after.wave_speed[i].to_bits(),
            before.wave_speed[i].to_bits(),
            "wave_speed[{i}] written"
        );
        assert_eq!(after.failed[i], before.failed[i], "failed[{i}] written");
        assert_eq!(after.status[i], before.status[i], "status[{i}] written");
        assert_eq!(
            bits(&after.tangent[36 * i..36 * i + 36]),
            bits(&before.tangent[36 * i..36 * i + 36]),
            "tangent of point {i} written"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// stoss_lsdyna_umat

fn umat(src: &mut Source, block: StossMaterialBlock) {
    // The card of the block (of 4340 if the block has no card), then host mistakes.
    let (values, length) = card_from_block(&block)
        .or_else(|_| card_from_block(&StossMaterialBlock::steel_4340()))
        .expect("4340 has a card");
    let mut card = values[..length].to_vec();
    let lmc = match src.byte() {
        240..=247 => usize::from(src.byte()) % (length + 1),
        248..=255 => {
            let extra = usize::from(src.choice(8)) + 1;
            for _ in 0..extra {
                card.push(if src.flag() { special(src) } else { 0.0 });
            }
            card.len()
        }
        _ => length,
    };
    for _ in 0..2 {
        if src.byte() >= 224 {
            let slot = usize::from(src.byte()) % card.len();
            card[slot] = special(src);
        }
    }

    let count = usize::from(src.count(1, 8));
    let nlq = match src.byte() % 8 {
        6 => usize::from(src.byte()) % (count + 1),
        7 => 0,
        _ => count,
    };
    let nhv = match src.byte() {
        240..=247 => usize::from(src.choice(8)),
        248..=255 => STOSS_HISTORY_COUNT + 1 + usize::from(src.choice(4)),
        _ => STOSS_HISTORY_COUNT,
    };
    let dt = time_step(src);
    // Column-major arrays for `count` points, read by the ABI with the stride `nlq`.
    let parsed_initial = initial_state_of(&block);
    let mut eps = vec![0.0; 6 * count];
    let mut sig = vec![0.0; 6 * count];
    let mut hsv = vec![0.0; nhv * count];
    for i in 0..count {
        for k in 0..6 {
            eps[i + count * k] = src.linear(-0.1, 0.1);
        }
        let state = point_state(src, &parsed_initial);
        for k in 0..6 {
            sig[i + count * k] = state.stress[k];
        }
        let history = match src.byte() {
            0..=63 => [0.0; STOSS_HISTORY_COUNT],
            248..=255 => {
                let mut history = history_from_state(&state);
                history[usize::from(src.choice(8))] = special(src);
                history
            }
            _ => history_from_state(&state),
        };
        for j in 0..nhv {
            hsv[i + count * j] = if j < STOSS_HISTORY_COUNT {
                history[j]
            } else {
                src.linear(-1.0, 1.0)
            };
        }
    }
    let mut pointers = UmatPointers::default();
    let outputs = src.byte();
    if outputs & 1 == 1 {
        pointers.failel = Pass::Null;
    }
    if outputs & 2 == 2 {
        pointers.wave_speed = Pass::Null;
    }
    if outputs & 4 == 4 {
        pointers.status = Pass::Null;
    }
    if src.byte() >= 200 {
        let how = pass(src);
        match src.choice(7) {
            0 => pointers.card = how,
            1 => pointers.eps = how,
            2 => pointers.sig = how,
            3 => pointers.hsv = how,
            4 => pointers.failel = how,
            5 => pointers.wave_speed = how,
            _ => pointers.status = how,
        }
    }
    let first_failure = src.byte() & 1 == 0;
    let capacity = message_capacity(src);
    let mut call = UmatCall {
        card,
        lmc,
        nlq,
        dt,
        eps,
        sig,
        hsv,
        nhv,
        failel: vec![CODE_SENTINEL; count],
        wave_speed: vec![WAVE_SENTINEL; count],
        status: vec![CODE_SENTINEL; count],
        first_failure,
        message_capacity: capacity,
        pointers,
    };
    let before = call.clone();
    let outcome = match lsdyna_umat(&mut call) {
        Ok(outcome) => outcome,
        Err(error) => panic!("harness: arrays shorter than the counts: {error}"),
    };
    check_status(outcome.status);
    check_umat(&before, &call, &outcome);
}

fn umat_call_error(call: &UmatCall) -> Option<CallError> {
    let p = &call.pointers;
    if let Some(error) = CallError::pointer(p.card, "cm", true) {
        return Some(error);
    }
    let used = call.lmc.min(STOSS_CARD_MAX_LENGTH);
    let material = block_from_card(&call.card[..used]).and_then(|block| block.to_model());
    if let Err(error) = material {
        return Some(CallError {
            status: error.status,
            field: error.message,
            exact: true,
        });
    }
    if call.nlq == 0 {
        return Some(CallError::field(StossStatus::ZeroPoints, "n"));
    }
    if call.nhv < STOSS_HISTORY_COUNT {
        return Some(CallError::field(StossStatus::BufferTooSmall, "nhv"));
    }
    for (pass, field) in [(p.eps, "eps"), (p.sig, "sig"), (p.hsv, "hsv")] {
        if let Some(error) = CallError::pointer(pass, field, true) {
            return Some(error);
        }
    }
    for (pass, field) in [
        (p.failel, "failel"),
        (p.wave_speed, "wave_speed"),
        (p.status, "status"),
    ] {
        if let Some(error) = CallError::pointer(pass, field, false) {
            return Some(error);
        }
    }
    None
}

fn check_umat(before: &UmatCall, after: &UmatCall, outcome: &CallOutcome) {
    assert_eq!(bits(&before.card), bits(&after.card), "card written");
    assert_eq!(bits(&before.eps), bits(&after.eps), "eps written");
    if let Some(error) = umat_call_error(before) {
        error.check(outcome);
        assert_eq!(
            bits(&before.sig),
            bits(&after.sig),
            "sig written on a call-level error"
        );
        assert_eq!(
            bits(&before.hsv),
            bits(&after.hsv),
            "hsv written on a call-level error"
        );
        assert_eq!(before.failel, after.failel);
        assert_eq!(bits(&before.wave_speed), bits(&after.wave_speed));
        assert_eq!(before.status, after.status);
        return;
    }
    let used = before.lmc.min(STOSS_CARD_MAX_LENGTH);
    let block = block_from_card(&before.card[..used]).expect("checked");
    let material = block.to_model().expect("checked");
    let initial = block.initial_state(&material);
    let nlq = before.nlq;
    let p = &before.pointers;
    let mut expected_sig = before.sig.clone();
    let mut expected_hsv = before.hsv.clone();
    let mut first: Option<(usize, UpdateError)> = None;
    for i in 0..nlq {
        let eps: [f64; 6] = std::array::from_fn(|k| before.eps[i + nlq * k]);
        let sig_in: [f64; 6] = std::array::from_fn(|k| before.sig[i + nlq * k]);
        let hsv_in: [f64; STOSS_HISTORY_COUNT] = std::array::from_fn(|j| before.hsv[i + nlq * j]);
        let (mut sig, mut hsv) = (sig_in, hsv_in);
        let result = lsdyna_umat_point(&material, &initial, before.dt, &eps, &mut sig, &mut hsv);
        let observed = (p.status == Pass::Valid).then(|| after.status[i]);
        if let Some(code) = observed {
            check_point_code(code);
        }
        let context = || {
            format!(
                "umat point {i} of {nlq}: eps {eps:?}, sig {sig_in:?}, hsv {hsv_in:?}, dt {}\n\
                 material {material:?}",
                before.dt
            )
        };
        match result {
            Ok((step, state)) => {
                assert!(
                    sig.iter().chain(hsv.iter()).all(|v| v.is_finite())
                        && step.wave_speed.is_finite(),
                    "OK with a non-finite stress, history or wave speed\n{}",
                    context()
                );
                for k in 0..6 {
                    expected_sig[i + nlq * k] = sig[k];
                }
                for j in 0..STOSS_HISTORY_COUNT {
                    expected_hsv[i + nlq * j] = hsv[j];
                }
                if let Some(code) = observed {
                    assert_eq!(code, StossStatus::Ok as i32, "{}", context());
                }
                if p.wave_speed == Pass::Valid {
                    assert_eq!(after.wave_speed[i].to_bits(), step.wave_speed.to_bits());
                }
                if p.failel == Pass::Valid {
                    assert_eq!(after.failel[i], failure_code(&state));
                }
            }
            Err(error) => {
                if let Some(code) = observed {
                    assert_eq!(code, StossStatus::from(error) as i32, "{}", context());
                }
                if p.wave_speed == Pass::Valid {
                    assert_eq!(after.wave_speed[i].to_bits(), WAVE_SENTINEL.to_bits());
                }
                if p.failel == Pass::Valid {
                    assert_eq!(after.failel[i], CODE_SENTINEL);
                }
                first.get_or_insert((i, error));
            }
        }
    }
    // Failing points keep sig and hsv; history beyond the eighth value and everything beyond
    // the nlq points is untouched.
    assert_eq!(
        bits(&after.sig),
        bits(&expected_sig),
        "sig differs from lsdyna_umat_point"
    );
    assert_eq!(
        bits(&after.hsv),
        bits(&expected_hsv),
        "hsv differs from lsdyna_umat_point"
    );
    for i in nlq..before.status.len() {
        assert_eq!(after.status[i], before.status[i]);
        assert_eq!(after.failel[i], before.failel[i]);
        assert_eq!(
            after.wave_speed[i].to_bits(),
            before.wave_speed[i].to_bits()
        );
    }
    match first {
        None => {
            assert_eq!(outcome.status, StossStatus::Ok);
            if let Some(index) = outcome.first_failure {
                assert_eq!(index, nlq);
            }
            check_message(&outcome.message, outcome.status, Expected::Exact(""));
        }
        Some((index, error)) => {
            assert_eq!(outcome.status, StossStatus::from(error));
            if let Some(reported) = outcome.first_failure {
                assert_eq!(reported, index);
            }
            let full = format!("point {index}: {error}");
            check_message(&outcome.message, outcome.status, Expected::Exact(&full));
        }
    }
}
