//! Safe Rust entry points to the exported C functions, for fuzzing and tests.
//!
//! [`update_batch`] and [`lsdyna_umat`] take owned Rust data (vectors, a material block by
//! value), build the pointer arguments a C host would build from them, call the real
//! `extern "C"` exports [`stoss_update_batch`] and [`stoss_lsdyna_umat`], and hand back the
//! status, the first-failure index, the message and the arrays as the call left them.
//!
//! They model the mistakes a host makes with its pointers and sizes, but only those whose
//! handling by the ABI is defined, so that code outside this crate can exercise the boundary
//! without any `unsafe` of its own:
//!
//! - any pointer may be passed as NULL ([`Pass::Null`]): the ABI must reject a required one
//!   and ignore an optional one;
//! - any pointer may be passed misaligned ([`Pass::Misaligned`]): one byte into a buffer that
//!   holds the data and one spare element, so even the misaligned range is in bounds; the ABI
//!   must reject it before any access;
//! - the block header may be corrupted (`layout_version`, `struct_size` are plain fields of
//!   the block value; the buffer behind the pointer is always a whole block);
//! - the point count may be anything up to what the buffers hold. A buffer *shorter* than the
//!   count the ABI is told cannot be passed safely (the ABI cannot detect it), so it is not
//!   representable: such a call returns [`LengthError`] without calling the ABI. "The host
//!   passed too small a count" is the representable form of that mistake.
//!
//! Nothing here is exported to C (no `#[no_mangle]`), so the header does not change.

use std::ffi::c_char;
use std::ptr::{null, null_mut};

use stoss_kernel::{MaterialState, StateFlags, YieldCheck};

use crate::abi::{stoss_lsdyna_umat, stoss_update_batch};
use crate::batch::{StossBatchInput, StossBatchOutput, StossBatchState};
use crate::block::StossMaterialBlock;
use crate::status::StossStatus;

/// Bytes after the message capacity that the ABI must never write (checked after the call).
const MESSAGE_GUARD: usize = 16;
/// Fill byte of message buffers and their guard.
const MESSAGE_FILL: u8 = 0x55;
/// Value of the first-failure slot before the call (the ABI writes it only once the points
/// were processed).
const FIRST_FAILURE_UNSET: usize = usize::MAX;

/// How one pointer argument is passed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Pass {
    /// A valid, aligned pointer to the data.
    #[default]
    Valid,
    /// NULL.
    Null,
    /// One byte past the start of a buffer that holds the data and one spare element:
    /// misaligned for every element type wider than a byte, yet in bounds.
    Misaligned,
}

/// A buffer the ABI was told is shorter than the count passed with it: not callable safely.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LengthError {
    /// The argument.
    pub field: &'static str,
    /// Elements the ABI may access for the counts passed (`None`: the count overflows).
    pub needed: Option<usize>,
    /// Elements the buffer holds.
    pub len: usize,
}

impl std::fmt::Display for LengthError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.needed {
            Some(needed) => write!(
                f,
                "{}: {} elements, the counts passed make the ABI access {needed}",
                self.field, self.len
            ),
            None => write!(f, "{}: element count overflows", self.field),
        }
    }
}

impl std::error::Error for LengthError {}

/// The message buffer after a call.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Message {
    /// The capacity passed to the ABI.
    pub capacity: usize,
    /// The `capacity` bytes of the buffer as the call left them (filled with `0x55` before).
    pub bytes: Vec<u8>,
    /// `false` if the ABI wrote any of the guard bytes after the capacity.
    pub guard_intact: bool,
}

impl Message {
    /// The bytes before the first NUL within the capacity; `None` if there is none.
    pub fn terminated(&self) -> Option<&[u8]> {
        let end = self.bytes.iter().position(|&b| b == 0)?;
        Some(&self.bytes[..end])
    }

    /// The message as text: `None` if it is not NUL-terminated within the capacity or not
    /// UTF-8.
    pub fn text(&self) -> Option<&str> {
        std::str::from_utf8(self.terminated()?).ok()
    }

    /// `true` if the buffer and its guard are exactly as before the call (what a capacity of
    /// 0 must give).
    pub fn untouched(&self) -> bool {
        self.guard_intact && self.bytes.iter().all(|&b| b == MESSAGE_FILL)
    }
}

/// What a call returned besides the arrays it updated in place.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CallOutcome {
    /// The return value.
    pub status: StossStatus,
    /// `None` if no first-failure pointer was passed; otherwise what the slot holds after
    /// the call (`usize::MAX` if the ABI did not write it).
    pub first_failure: Option<usize>,
    /// `None` if the message pointer was NULL.
    pub message: Option<Message>,
}

impl CallOutcome {
    /// The value the first-failure slot holds before a call.
    pub fn first_failure_unset() -> usize {
        FIRST_FAILURE_UNSET
    }
}

/// A batch state as owned arrays (structure of arrays, as `StossBatchState` points to).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BatchStateData {
    /// Cauchy stress, Voigt order.
    pub stress: [Vec<f64>; 6],
    /// Equivalent plastic strain.
    pub plastic_strain: Vec<f64>,
    /// Plastic strain rate of the last step.
    pub plastic_strain_rate: Vec<f64>,
    /// Temperature.
    pub temperature: Vec<f64>,
    /// Damage.
    pub damage: Vec<f64>,
    /// Relative volume.
    pub relative_volume: Vec<f64>,
    /// Internal energy per reference volume.
    pub internal_energy: Vec<f64>,
    /// EoS history variable.
    pub eos_history: Vec<f64>,
    /// State flags.
    pub flags: Vec<u32>,
}

impl BatchStateData {
    /// The arrays of `points`.
    pub fn from_points(points: &[MaterialState]) -> Self {
        let column = |f: &dyn Fn(&MaterialState) -> f64| points.iter().map(f).collect();
        Self {
            stress: std::array::from_fn(|k| column(&|p| p.stress[k])),
            plastic_strain: column(&|p| p.plastic_strain),
            plastic_strain_rate: column(&|p| p.plastic_strain_rate),
            temperature: column(&|p| p.temperature),
            damage: column(&|p| p.damage),
            relative_volume: column(&|p| p.relative_volume),
            internal_energy: column(&|p| p.internal_energy),
            eos_history: column(&|p| p.eos_history),
            flags: points.iter().map(|p| p.flags.0).collect(),
        }
    }

    /// Number of points every array holds (the shortest array).
    pub fn len(&self) -> usize {
        self.stress
            .iter()
            .map(Vec::len)
            .chain(self.scalars().iter().map(|a| a.len()))
            .chain([self.flags.len()])
            .min()
            .unwrap_or(0)
    }

    /// `true` if some array is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Point `i` (`None` if an array is too short).
    pub fn point(&self, i: usize) -> Option<MaterialState> {
        if i >= self.len() {
            return None;
        }
        Some(MaterialState {
            stress: std::array::from_fn(|k| self.stress[k][i]),
            plastic_strain: self.plastic_strain[i],
            plastic_strain_rate: self.plastic_strain_rate[i],
            temperature: self.temperature[i],
            damage: self.damage[i],
            relative_volume: self.relative_volume[i],
            internal_energy: self.internal_energy[i],
            eos_history: self.eos_history[i],
            flags: StateFlags(self.flags[i]),
            yield_check: YieldCheck::NONE,
        })
    }

    fn scalars(&self) -> [&Vec<f64>; 7] {
        [
            &self.plastic_strain,
            &self.plastic_strain_rate,
            &self.temperature,
            &self.damage,
            &self.relative_volume,
            &self.internal_energy,
            &self.eos_history,
        ]
    }
}

/// How each pointer of a [`BatchCall`] is passed (all valid by default).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BatchPointers {
    /// `block`.
    pub block: Pass,
    /// `input` (the struct).
    pub input: Pass,
    /// `input->strain_increment[k]`.
    pub strain_increment: [Pass; 6],
    /// `input->relative_volume` (NULL is allowed: volumes integrated).
    pub relative_volume: Pass,
    /// `state` (the struct).
    pub state: Pass,
    /// The 14 arrays of the state in the order of `StossBatchState`: `stress[0..6]`,
    /// `plastic_strain`, `plastic_strain_rate`, `temperature`, `damage`, `relative_volume`,
    /// `internal_energy`, `eos_history`, `flags`.
    pub state_arrays: [Pass; 14],
    /// `output` (the struct; NULL is allowed: no outputs).
    pub output: Pass,
    /// `output->wave_speed` (NULL allowed).
    pub wave_speed: Pass,
    /// `output->failed` (NULL allowed).
    pub failed: Pass,
    /// `output->status` (NULL allowed).
    pub status: Pass,
    /// `output->tangent` (NULL allowed).
    pub tangent: Pass,
}

/// The arguments of one `stoss_update_batch` call, owned.
#[derive(Clone, Debug, Default)]
pub struct BatchCall {
    /// The material block (its header fields may be anything).
    pub block: StossMaterialBlock,
    /// The point count passed (at most what every passed array holds).
    pub n: usize,
    /// Time step.
    pub dt: f64,
    /// `input->strain_increment`.
    pub strain_increment: [Vec<f64>; 6],
    /// `input->relative_volume` (passed only if `pointers.relative_volume` is not NULL).
    pub relative_volume: Vec<f64>,
    /// The state, updated in place.
    pub state: BatchStateData,
    /// `output->wave_speed`.
    pub wave_speed: Vec<f64>,
    /// `output->failed`.
    pub failed: Vec<i32>,
    /// `output->status` (per point).
    pub status: Vec<i32>,
    /// `output->tangent` (36 values per point).
    pub tangent: Vec<f64>,
    /// Pass a `first_failure` pointer.
    pub first_failure: bool,
    /// Message capacity; `None`: NULL message pointer.
    pub message_capacity: Option<usize>,
    /// How each pointer is passed.
    pub pointers: BatchPointers,
}

/// The arguments of one `stoss_lsdyna_umat` call, owned (column-major arrays).
#[derive(Clone, Debug, Default)]
pub struct UmatCall {
    /// `cm`.
    pub card: Vec<f64>,
    /// `lmc` (at most `card.len()`).
    pub lmc: usize,
    /// `nlq`.
    pub nlq: usize,
    /// Time step.
    pub dt: f64,
    /// `eps(nlq, 6)`, engineering shear.
    pub eps: Vec<f64>,
    /// `sig(nlq, 6)`, updated in place.
    pub sig: Vec<f64>,
    /// `hsv(nlq, nhv)`, updated in place.
    pub hsv: Vec<f64>,
    /// `nhv`.
    pub nhv: usize,
    /// `failel(nlq)`.
    pub failel: Vec<i32>,
    /// `wave_speed(nlq)`.
    pub wave_speed: Vec<f64>,
    /// `status(nlq)`.
    pub status: Vec<i32>,
    /// Pass a `first_failure` pointer.
    pub first_failure: bool,
    /// Message capacity; `None`: NULL message pointer.
    pub message_capacity: Option<usize>,
    /// How each pointer is passed.
    pub pointers: UmatPointers,
}

/// How each pointer of a [`UmatCall`] is passed (all valid by default).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UmatPointers {
    /// `cm`.
    pub card: Pass,
    /// `eps`.
    pub eps: Pass,
    /// `sig`.
    pub sig: Pass,
    /// `hsv`.
    pub hsv: Pass,
    /// `failel` (NULL allowed).
    pub failel: Pass,
    /// `wave_speed` (NULL allowed).
    pub wave_speed: Pass,
    /// `status` (NULL allowed).
    pub status: Pass,
}

/// A caller's vector lent to the ABI as one pointer argument. For [`Pass::Misaligned`] one
/// spare element is appended (so that the range one byte in stays in bounds) and removed
/// again by [`Lent::restore`].
struct Lent<'a, T> {
    values: &'a mut Vec<T>,
    len: usize,
    pass: Pass,
}

impl<'a, T: Copy> Lent<'a, T> {
    /// Lend `values` (its length was checked against the counts passed beforehand).
    fn new(values: &'a mut Vec<T>, pass: Pass, spare: T) -> Self {
        let len = values.len();
        if pass == Pass::Misaligned {
            values.push(spare);
        }
        Self { values, len, pass }
    }

    /// The pointer to pass. Safe code: nothing is dereferenced here.
    fn pointer(&mut self) -> *mut T {
        match self.pass {
            Pass::Valid => self.values.as_mut_ptr(),
            Pass::Null => null_mut(),
            Pass::Misaligned => self
                .values
                .as_mut_ptr()
                .cast::<u8>()
                .wrapping_add(1)
                .cast::<T>(),
        }
    }

    fn restore(self) {
        self.values.truncate(self.len);
    }
}

/// A buffer of `len` elements passed as `pass` must hold the `needed` elements the ABI may
/// access (`None`: the count overflowed); a NULL pointer needs nothing.
fn check_length(
    len: usize,
    pass: Pass,
    needed: Option<usize>,
    field: &'static str,
) -> Result<(), LengthError> {
    if pass != Pass::Null && needed.is_none_or(|needed| needed > len) {
        Err(LengthError { field, needed, len })
    } else {
        Ok(())
    }
}

/// A struct argument (block, input, state, output) in a buffer of two copies, so that a
/// misaligned pointer one byte in still points into initialised memory.
fn struct_pointer<T: Copy>(buffer: &mut [T; 2], pass: Pass) -> *mut T {
    match pass {
        Pass::Valid => buffer.as_mut_ptr(),
        Pass::Null => null_mut(),
        Pass::Misaligned => buffer.as_mut_ptr().cast::<u8>().wrapping_add(1).cast::<T>(),
    }
}

/// The message buffer: `capacity` fill bytes and a guard.
struct MessageBuffer {
    capacity: usize,
    bytes: Option<Vec<c_char>>,
}

impl MessageBuffer {
    fn new(capacity: Option<usize>) -> Self {
        Self {
            capacity: capacity.unwrap_or(0),
            bytes: capacity.map(|c| vec![MESSAGE_FILL as c_char; c + MESSAGE_GUARD]),
        }
    }

    fn pointer(&mut self) -> *mut c_char {
        self.bytes.as_mut().map_or(null_mut(), |b| b.as_mut_ptr())
    }

    fn finish(self) -> Option<Message> {
        let capacity = self.capacity;
        self.bytes.map(|bytes| {
            let bytes: Vec<u8> = bytes.into_iter().map(|c| c as u8).collect();
            Message {
                capacity,
                guard_intact: bytes[capacity..].iter().all(|&b| b == MESSAGE_FILL),
                bytes: bytes[..capacity].to_vec(),
            }
        })
    }
}

const STRAIN_FIELDS: [&str; 6] = [
    "input.strain_increment[0]",
    "input.strain_increment[1]",
    "input.strain_increment[2]",
    "input.strain_increment[3]",
    "input.strain_increment[4]",
    "input.strain_increment[5]",
];
const STATE_FIELDS: [&str; 14] = [
    "state.stress[0]",
    "state.stress[1]",
    "state.stress[2]",
    "state.stress[3]",
    "state.stress[4]",
    "state.stress[5]",
    "state.plastic_strain",
    "state.plastic_strain_rate",
    "state.temperature",
    "state.damage",
    "state.relative_volume",
    "state.internal_energy",
    "state.eos_history",
    "state.flags",
];

/// Call `stoss_update_batch` with `call`'s data, exactly as a C host would; the state and
/// output arrays of `call` are updated in place (the inputs and the block are left as they
/// were). `Err` (and no call) if a passed array is shorter than `n` (`36 n` for the tangent).
pub fn update_batch(call: &mut BatchCall) -> Result<CallOutcome, LengthError> {
    let n = call.n;
    let p = call.pointers;
    let tangent_len = n.checked_mul(36);

    // Length checks first, for every array the pointers make the ABI see (before any
    // vector is touched, so that an error leaves `call` as it was).
    for (k, array) in call.strain_increment.iter().enumerate() {
        check_length(
            array.len(),
            p.strain_increment[k],
            Some(n),
            STRAIN_FIELDS[k],
        )?;
    }
    check_length(
        call.relative_volume.len(),
        p.relative_volume,
        Some(n),
        "input.relative_volume",
    )?;
    let s = &call.state;
    let state_lens = [
        s.stress[0].len(),
        s.stress[1].len(),
        s.stress[2].len(),
        s.stress[3].len(),
        s.stress[4].len(),
        s.stress[5].len(),
        s.plastic_strain.len(),
        s.plastic_strain_rate.len(),
        s.temperature.len(),
        s.damage.len(),
        s.relative_volume.len(),
        s.internal_energy.len(),
        s.eos_history.len(),
        s.flags.len(),
    ];
    for (j, len) in state_lens.into_iter().enumerate() {
        check_length(len, p.state_arrays[j], Some(n), STATE_FIELDS[j])?;
    }
    check_length(
        call.wave_speed.len(),
        p.wave_speed,
        Some(n),
        "output.wave_speed",
    )?;
    check_length(call.failed.len(), p.failed, Some(n), "output.failed")?;
    check_length(call.status.len(), p.status, Some(n), "output.status")?;
    check_length(call.tangent.len(), p.tangent, tangent_len, "output.tangent")?;

    let mut block = [call.block; 2];
    let block_pointer = struct_pointer(&mut block, p.block).cast_const();

    // Lend every array (lengths checked above).
    let [s0, s1, s2, s3, s4, s5] = &mut call.strain_increment;
    let mut strain: Vec<Lent<'_, f64>> = Vec::with_capacity(6);
    for (k, values) in [s0, s1, s2, s3, s4, s5].into_iter().enumerate() {
        strain.push(Lent::new(values, p.strain_increment[k], 0.0));
    }
    let mut volume = Lent::new(&mut call.relative_volume, p.relative_volume, 0.0);
    let BatchStateData {
        stress,
        plastic_strain,
        plastic_strain_rate,
        temperature,
        damage,
        relative_volume,
        internal_energy,
        eos_history,
        flags,
    } = &mut call.state;
    let [t0, t1, t2, t3, t4, t5] = stress;
    let mut state_arrays: Vec<Lent<'_, f64>> = Vec::with_capacity(13);
    for (j, values) in [
        t0,
        t1,
        t2,
        t3,
        t4,
        t5,
        plastic_strain,
        plastic_strain_rate,
        temperature,
        damage,
        relative_volume,
        internal_energy,
        eos_history,
    ]
    .into_iter()
    .enumerate()
    {
        state_arrays.push(Lent::new(values, p.state_arrays[j], 0.0));
    }
    let mut flags = Lent::new(flags, p.state_arrays[13], 0);
    let mut wave_speed = Lent::new(&mut call.wave_speed, p.wave_speed, 0.0);
    let mut failed = Lent::new(&mut call.failed, p.failed, 0);
    let mut status = Lent::new(&mut call.status, p.status, 0);
    let mut tangent = Lent::new(&mut call.tangent, p.tangent, 0.0);

    let input = StossBatchInput {
        strain_increment: std::array::from_fn(|k| strain[k].pointer().cast_const()),
        relative_volume: volume.pointer().cast_const(),
    };
    let state = StossBatchState {
        stress: std::array::from_fn(|k| state_arrays[k].pointer()),
        plastic_strain: state_arrays[6].pointer(),
        plastic_strain_rate: state_arrays[7].pointer(),
        temperature: state_arrays[8].pointer(),
        damage: state_arrays[9].pointer(),
        relative_volume: state_arrays[10].pointer(),
        internal_energy: state_arrays[11].pointer(),
        eos_history: state_arrays[12].pointer(),
        flags: flags.pointer(),
    };
    let output = StossBatchOutput {
        wave_speed: wave_speed.pointer(),
        failed: failed.pointer(),
        status: status.pointer(),
        tangent: tangent.pointer(),
    };
    let mut input = [input; 2];
    let mut state = [state; 2];
    let mut output = [output; 2];
    let input_pointer = struct_pointer(&mut input, p.input).cast_const();
    let state_pointer = struct_pointer(&mut state, p.state).cast_const();
    let output_pointer = struct_pointer(&mut output, p.output).cast_const();
    let mut first_failure = FIRST_FAILURE_UNSET;
    let first_failure_pointer = if call.first_failure {
        &raw mut first_failure
    } else {
        null_mut()
    };
    let mut message = MessageBuffer::new(call.message_capacity);
    let message_pointer = message.pointer();

    // SAFETY: every pointer is NULL, or points into a buffer owned by this function or
    // lent from `call` (`Lent`, `struct_pointer`, `MessageBuffer`) that stays alive and is not
    // accessed through any other path until the call returns. Valid array pointers hold at
    // least `n` elements (`36 n` for the tangent), checked above; misaligned pointers are one
    // byte into such a buffer plus one spare element (in bounds), and the export rejects them
    // before any access; the block pointer points to a whole `StossMaterialBlock` (header
    // fields may be anything: the export reads the 8-byte header first); the struct pointers
    // point to whole, initialised structs; `first_failure` is NULL or a local `usize`; the
    // message buffer holds `capacity + MESSAGE_GUARD` bytes.
    let returned = unsafe {
        stoss_update_batch(
            block_pointer,
            n,
            call.dt,
            input_pointer,
            state_pointer,
            output_pointer,
            first_failure_pointer,
            message_pointer,
            message.capacity,
        )
    };

    for lent in strain.into_iter().chain([volume]).chain(state_arrays) {
        lent.restore();
    }
    flags.restore();
    wave_speed.restore();
    failed.restore();
    status.restore();
    tangent.restore();
    Ok(CallOutcome {
        status: returned,
        first_failure: call.first_failure.then_some(first_failure),
        message: message.finish(),
    })
}

/// Call `stoss_lsdyna_umat` with `call`'s data, exactly as a Fortran or C host would; `sig`,
/// `hsv` and the optional outputs of `call` are updated in place. `Err` (and no call) if a
/// passed array is shorter than the counts say (`lmc` values of the card, `6 nlq` of `eps`
/// and `sig`, `nhv nlq` of `hsv`, `nlq` of each optional output).
pub fn lsdyna_umat(call: &mut UmatCall) -> Result<CallOutcome, LengthError> {
    let nlq = call.nlq;
    let p = call.pointers;
    let components = nlq.checked_mul(6);
    let history = nlq.checked_mul(call.nhv);
    check_length(call.card.len(), p.card, Some(call.lmc), "cm")?;
    check_length(call.eps.len(), p.eps, components, "eps")?;
    check_length(call.sig.len(), p.sig, components, "sig")?;
    check_length(call.hsv.len(), p.hsv, history, "hsv")?;
    check_length(call.failel.len(), p.failel, Some(nlq), "failel")?;
    check_length(call.wave_speed.len(), p.wave_speed, Some(nlq), "wave_speed")?;
    check_length(call.status.len(), p.status, Some(nlq), "status")?;

    let mut card = Lent::new(&mut call.card, p.card, 0.0);
    let mut eps = Lent::new(&mut call.eps, p.eps, 0.0);
    let mut sig = Lent::new(&mut call.sig, p.sig, 0.0);
    let mut hsv = Lent::new(&mut call.hsv, p.hsv, 0.0);
    let mut failel = Lent::new(&mut call.failel, p.failel, 0);
    let mut wave_speed = Lent::new(&mut call.wave_speed, p.wave_speed, 0.0);
    let mut status = Lent::new(&mut call.status, p.status, 0);
    let mut first_failure = FIRST_FAILURE_UNSET;
    let first_failure_pointer = if call.first_failure {
        &raw mut first_failure
    } else {
        null_mut()
    };
    let mut message = MessageBuffer::new(call.message_capacity);
    let message_pointer = message.pointer();
    let card_pointer = if p.card == Pass::Null {
        null()
    } else {
        card.pointer().cast_const()
    };

    // SAFETY: every pointer is NULL, or points into a vector lent from `call` (`Lent`) or a
    // local, alive and not accessed through any other path until the call returns. Valid
    // pointers hold at least the elements the export's contract asks for with the counts
    // passed (`lmc`, `6 nlq`, `nhv nlq`, `nlq`), checked above; misaligned pointers are one
    // byte into such a buffer plus one spare element (in bounds) and are rejected by the
    // export before any access; `first_failure` is NULL or a local `usize`; the message
    // buffer holds `capacity + MESSAGE_GUARD` bytes.
    let returned = unsafe {
        stoss_lsdyna_umat(
            card_pointer,
            call.lmc,
            nlq,
            call.dt,
            eps.pointer().cast_const(),
            sig.pointer(),
            hsv.pointer(),
            call.nhv,
            failel.pointer(),
            wave_speed.pointer(),
            status.pointer(),
            first_failure_pointer,
            message_pointer,
            message.capacity,
        )
    };

    card.restore();
    eps.restore();
    sig.restore();
    hsv.restore();
    failel.restore();
    wave_speed.restore();
    status.restore();
    Ok(CallOutcome {
        status: returned,
        first_failure: call.first_failure.then_some(first_failure),
        message: message.finish(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::adapters::STOSS_HISTORY_COUNT;
    use crate::card::card_from_block;

    fn batch(n: usize) -> BatchCall {
        let block = StossMaterialBlock::steel_4340();
        let initial = MaterialState::initial(298.0);
        let mut strain: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; n]);
        strain[0] = (0..n).map(|i| -1e-3 * (i as f64 + 1.0)).collect();
        BatchCall {
            block,
            n,
            dt: 1e-7,
            strain_increment: strain,
            relative_volume: vec![1.0; n],
            state: BatchStateData::from_points(&vec![initial; n]),
            wave_speed: vec![-1.0; n],
            failed: vec![-1; n],
            status: vec![-1; n],
            tangent: vec![0.0; 36 * n],
            first_failure: true,
            message_capacity: Some(128),
            pointers: BatchPointers {
                relative_volume: Pass::Null,
                ..BatchPointers::default()
            },
        }
    }

    #[test]
    fn a_valid_batch_updates_every_point() {
        let mut call = batch(3);
        let outcome = update_batch(&mut call).unwrap();
        assert_eq!(outcome.status, StossStatus::Ok);
        assert_eq!(outcome.first_failure, Some(3));
        let message = outcome.message.unwrap();
        assert_eq!(message.text(), Some(""));
        assert!(message.guard_intact);
        assert_eq!(call.status, vec![0; 3]);
        assert!(call.wave_speed.iter().all(|c| c.is_finite() && *c > 0.0));
        assert!(call.state.stress[0].iter().all(|s| *s < 0.0));
        assert_eq!(call.state.len(), 3);
        assert_eq!(call.tangent.len(), 108);
    }

    #[test]
    fn bad_pointers_header_and_counts_get_their_status() {
        let mut call = batch(2);
        call.pointers.block = Pass::Null;
        let outcome = update_batch(&mut call).unwrap();
        assert_eq!(outcome.status, StossStatus::NullPointer);
        assert!(outcome
            .message
            .unwrap()
            .text()
            .unwrap()
            .starts_with("block:"));

        let mut call = batch(2);
        call.pointers.state_arrays[9] = Pass::Misaligned;
        let before = call.state.clone();
        let outcome = update_batch(&mut call).unwrap();
        assert_eq!(outcome.status, StossStatus::MisalignedPointer);
        assert_eq!(outcome.first_failure, Some(usize::MAX));
        assert_eq!(call.state, before);
        assert_eq!(call.state.damage.len(), 2);

        let mut call = batch(2);
        call.block.layout_version = crate::block::STOSS_LAYOUT_VERSION + 1;
        assert_eq!(
            update_batch(&mut call).unwrap().status,
            StossStatus::BadLayoutVersion
        );

        let mut call = batch(2);
        call.n = 0;
        assert_eq!(
            update_batch(&mut call).unwrap().status,
            StossStatus::ZeroPoints
        );

        // n = 1 of 2: the second point is not touched.
        let mut call = batch(2);
        call.n = 1;
        let before = call.state.point(1);
        assert_eq!(update_batch(&mut call).unwrap().status, StossStatus::Ok);
        assert_eq!(call.state.point(1), before);
        assert_eq!(call.status, vec![0, -1]);
    }

    #[test]
    fn a_nan_strain_fails_its_point_only() {
        let mut call = batch(3);
        call.strain_increment[4][1] = f64::NAN;
        let before = call.state.point(1).unwrap();
        let outcome = update_batch(&mut call).unwrap();
        assert_eq!(outcome.status, StossStatus::NonFiniteInput);
        assert_eq!(outcome.first_failure, Some(1));
        assert_eq!(call.status, vec![0, StossStatus::NonFiniteInput as i32, 0]);
        assert_eq!(call.state.point(1).unwrap(), before);
        assert!(outcome
            .message
            .unwrap()
            .text()
            .unwrap()
            .starts_with("point 1:"));
    }

    #[test]
    fn messages_stay_within_their_capacity() {
        for capacity in [0, 1, 2, 5] {
            let mut call = batch(1);
            call.dt = -1.0;
            call.message_capacity = Some(capacity);
            let outcome = update_batch(&mut call).unwrap();
            assert_eq!(outcome.status, StossStatus::NonPositiveTimeStep);
            let message = outcome.message.unwrap();
            assert!(message.guard_intact);
            if capacity == 0 {
                assert!(message.untouched());
            } else {
                let text = message.text().unwrap();
                assert!(text.len() < capacity);
                assert!("point 0: ".starts_with(text) || text.starts_with("point 0:"));
            }
        }
        let mut call = batch(1);
        call.message_capacity = None;
        call.first_failure = false;
        let outcome = update_batch(&mut call).unwrap();
        assert_eq!((outcome.message, outcome.first_failure), (None, None));
    }

    #[test]
    fn short_buffers_are_not_callable() {
        let mut call = batch(2);
        call.state.temperature.pop();
        let error = update_batch(&mut call).unwrap_err();
        assert_eq!(error.field, "state.temperature");
        assert_eq!((error.needed, error.len), (Some(2), 1));
        // ... unless that pointer is NULL, which the ABI rejects.
        call.pointers.state_arrays[8] = Pass::Null;
        assert_eq!(
            update_batch(&mut call).unwrap().status,
            StossStatus::NullPointer
        );
        let mut call = batch(2);
        call.tangent.truncate(36);
        assert_eq!(update_batch(&mut call).unwrap_err().field, "output.tangent");
        call.pointers.tangent = Pass::Null;
        assert_eq!(update_batch(&mut call).unwrap().status, StossStatus::Ok);
    }

    fn umat(nlq: usize) -> UmatCall {
        let (card, length) = card_from_block(&StossMaterialBlock::steel_4340()).unwrap();
        let mut eps = vec![0.0; 6 * nlq];
        for i in 0..nlq {
            eps[i + nlq * 3] = 2e-3;
        }
        UmatCall {
            card: card[..length].to_vec(),
            lmc: length,
            nlq,
            dt: 1e-7,
            eps,
            sig: vec![0.0; 6 * nlq],
            hsv: vec![0.0; STOSS_HISTORY_COUNT * nlq],
            nhv: STOSS_HISTORY_COUNT,
            failel: vec![-1; nlq],
            wave_speed: vec![-1.0; nlq],
            status: vec![-1; nlq],
            first_failure: true,
            message_capacity: Some(64),
            pointers: UmatPointers::default(),
        }
    }

    #[test]
    fn umat_calls_reach_the_adapter() {
        let mut call = umat(2);
        let outcome = update_umat(&mut call);
        assert_eq!(outcome.status, StossStatus::Ok);
        assert_eq!(outcome.first_failure, Some(2));
        assert!(call.sig[2 * 3] > 0.0 && call.sig[2 * 3 + 1] > 0.0);
        assert_eq!(call.hsv[2 * 4], 1.0);

        let mut call = umat(2);
        call.pointers.card = Pass::Null;
        assert_eq!(update_umat(&mut call).status, StossStatus::NullPointer);
        let mut call = umat(2);
        call.pointers.hsv = Pass::Misaligned;
        let before = call.hsv.clone();
        assert_eq!(
            update_umat(&mut call).status,
            StossStatus::MisalignedPointer
        );
        assert_eq!(call.hsv, before);
        let mut call = umat(2);
        call.card[0] = f64::from(crate::block::STOSS_LAYOUT_VERSION + 1);
        assert_eq!(update_umat(&mut call).status, StossStatus::BadLayoutVersion);
        let mut call = umat(2);
        call.nhv = 7;
        assert_eq!(update_umat(&mut call).status, StossStatus::BufferTooSmall);
        let mut call = umat(2);
        call.lmc = call.card.len() + 1;
        assert_eq!(lsdyna_umat(&mut call).unwrap_err().field, "cm");
    }

    fn update_umat(call: &mut UmatCall) -> CallOutcome {
        lsdyna_umat(call).unwrap()
    }
}
