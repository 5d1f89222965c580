//! The exported C functions. Each one is a thin shell: check the pointers, run the body
//! through [`boundary`], return a [`StossStatus`].
//!
//! Conventions shared by every function:
//! - `message`/`message_capacity`: a caller-owned buffer that receives a NUL-terminated
//!   message (truncated to fit), naming the field or the point index on failure, the empty
//!   string on success. May be NULL (or capacity 0): no message.
//! - Every function is reentrant and thread-safe: no global or static mutable state, no
//!   allocation that outlives the call, no I/O. Different threads may call concurrently on
//!   disjoint arrays with the same (read-only) material block.
//! - Arrays are caller-owned, never retained after the call returns.

use std::ffi::c_char;

use crate::adapters::{run_lsdyna, run_vumat, LsDynaArrays, VumatArrays, STOSS_HISTORY_COUNT};
use crate::batch::AbiModel;
use crate::batch::{
    run_batch, InputViews, OutputViews, StateViews, StossBatchInput, StossBatchOutput,
    StossBatchState,
};
use crate::block::{initial_bulk_modulus, StossMaterialBlock, BLOCK_SIZE, STOSS_LAYOUT_VERSION};
use stoss_kernel::{PartMaterial, PointModel};

/// Run `$body` with `$m` bound to the J2 metal, the RHT or the K&C concrete of a
/// [`PartMaterial`]:
/// the body is compiled once per family, so no point pays for the dispatch.
macro_rules! per_family {
    ($model:expr, $m:ident => $body:expr) => {
        match $model {
            PartMaterial::J2(ref $m) => $body,
            PartMaterial::Rht(ref $m) => $body,
            PartMaterial::Kc(ref $m) => $body,
        }
    };
}
use crate::boundary::{
    boundary, check_optional_pointer, read_struct, write_optional, write_struct, ArrayIn, ArrayOut,
};
use crate::card::{block_from_card, card_from_block, STOSS_CARD_MAX_LENGTH};
use crate::status::{FfiError, StossStatus};

/// Read a material block: header first (version, size), then the whole struct.
///
/// # Safety
/// `block` is NULL or points to at least 8 readable bytes; if its header matches this
/// library, to a readable, initialised `StossMaterialBlock`.
unsafe fn read_block(block: *const StossMaterialBlock) -> Result<StossMaterialBlock, FfiError> {
    if block.is_null() {
        return Err(FfiError::null("block"));
    }
    if !block.is_aligned() {
        return Err(FfiError::new(
            StossStatus::MisalignedPointer,
            format!("block: pointer {block:p} is not aligned to 8 bytes"),
        ));
    }
    let header = block.cast::<u32>();
    // SAFETY: non-NULL, aligned (8 >= 4), and the first two `u32` fields of the `repr(C)`
    // block are readable (caller contract) whatever the version of the caller's header.
    let (version, size) = unsafe { (header.read(), header.add(1).read()) };
    StossMaterialBlock::check_header(version, size)?;
    // SAFETY: the header says the caller's struct is this library's struct (same version
    // and size); readable and initialised (caller contract).
    Ok(unsafe { block.read() })
}

/// The first `STOSS_CARD_MAX_LENGTH` values of a card (values beyond are never read by any
/// card layout) on the stack, and how many there are.
fn copy_card(card: &ArrayIn<'_, f64>, length: usize) -> ([f64; STOSS_CARD_MAX_LENGTH], usize) {
    let used = length.min(STOSS_CARD_MAX_LENGTH);
    let mut values = [0.0; STOSS_CARD_MAX_LENGTH];
    for (i, value) in values.iter_mut().enumerate().take(used) {
        *value = card.get(i);
    }
    (values, used)
}

fn zero_points(n: usize) -> Result<(), FfiError> {
    if n == 0 {
        Err(FfiError::new(
            StossStatus::ZeroPoints,
            "n: zero points (nothing to update)",
        ))
    } else {
        Ok(())
    }
}

fn product(a: usize, b: usize, what: &str) -> Result<usize, FfiError> {
    a.checked_mul(b).ok_or_else(|| {
        FfiError::new(
            StossStatus::InvalidArgument,
            format!("{what}: {a} x {b} overflows"),
        )
    })
}

/// Report the first failing point after the whole batch was processed.
fn report(
    n: usize,
    first_failure: Option<(usize, stoss_kernel::UpdateError)>,
    first_failure_out: *mut usize,
) -> Result<(), FfiError> {
    let index = first_failure.map_or(n, |(i, _)| i);
    // SAFETY: `first_failure_out` is NULL or valid for one `size_t` (caller contract of every
    // export that takes it).
    unsafe { write_optional(first_failure_out, index, "first_failure") }?;
    match first_failure {
        Some((i, error)) => Err(FfiError::update(i, error)),
        None => Ok(()),
    }
}

/// Layout version of `StossMaterialBlock` and of the card this library was built with
/// (`STOSS_LAYOUT_VERSION` of its header).
#[no_mangle]
pub extern "C" fn stoss_layout_version() -> u32 {
    STOSS_LAYOUT_VERSION
}

/// `sizeof(StossMaterialBlock)` of this library (compare with the host's).
#[no_mangle]
pub extern "C" fn stoss_material_block_size() -> u32 {
    BLOCK_SIZE
}

/// The name of a status code as a static NUL-terminated string, e.g.
/// `"STOSS_STATUS_NULL_POINTER"`; `"STOSS_STATUS_UNKNOWN"` for numbers without a meaning.
/// Never NULL; never free it.
#[no_mangle]
pub extern "C" fn stoss_status_name(status: i32) -> *const c_char {
    let name: &'static std::ffi::CStr = match StossStatus::from_code(status) {
        Some(StossStatus::Ok) => c"STOSS_STATUS_OK",
        Some(StossStatus::NullPointer) => c"STOSS_STATUS_NULL_POINTER",
        Some(StossStatus::Panic) => c"STOSS_STATUS_PANIC",
        Some(StossStatus::BadLayoutVersion) => c"STOSS_STATUS_BAD_LAYOUT_VERSION",
        Some(StossStatus::InvalidParameter) => c"STOSS_STATUS_INVALID_PARAMETER",
        Some(StossStatus::NonFiniteInput) => c"STOSS_STATUS_NON_FINITE_INPUT",
        Some(StossStatus::NonPositiveTimeStep) => c"STOSS_STATUS_NON_POSITIVE_TIME_STEP",
        Some(StossStatus::NonPositiveVolume) => c"STOSS_STATUS_NON_POSITIVE_VOLUME",
        Some(StossStatus::ReturnMappingDiverged) => c"STOSS_STATUS_RETURN_MAPPING_DIVERGED",
        Some(StossStatus::ZeroPoints) => c"STOSS_STATUS_ZERO_POINTS",
        Some(StossStatus::BufferTooSmall) => c"STOSS_STATUS_BUFFER_TOO_SMALL",
        Some(StossStatus::BadStructSize) => c"STOSS_STATUS_BAD_STRUCT_SIZE",
        Some(StossStatus::NonFiniteState) => c"STOSS_STATUS_NON_FINITE_STATE",
        Some(StossStatus::NonFiniteResult) => c"STOSS_STATUS_NON_FINITE_RESULT",
        Some(StossStatus::InvalidArgument) => c"STOSS_STATUS_INVALID_ARGUMENT",
        Some(StossStatus::MisalignedPointer) => c"STOSS_STATUS_MISALIGNED_POINTER",
        Some(StossStatus::InadmissibleState) => c"STOSS_STATUS_INADMISSIBLE_STATE",
        None => c"STOSS_STATUS_UNKNOWN",
    };
    name.as_ptr()
}

/// Fill `block` with 4340 steel: Johnson & Cook (1985) strength (A 792 MPa, B 510 MPa,
/// n 0.26, C 0.014, m 1.03, e0 1/s, Tr 298 K, Tm 1793 K), linear EoS K 159 GPa, G 81.8 GPa,
/// rho 7830 kg/m^3, c_p 477 J/kg/K, adiabatic heating chi 0.9, implicit rate, initial
/// temperature 298 K; JC failure constants of 4340 (D1..D5 = 0.05 3.44 -2.12 0.002 0.61)
/// filled in but switched off. Every field of the block is written (unused families zero),
/// including `layout_version` and `struct_size`.
///
/// # Safety
/// `block` is NULL or valid for writes of one `StossMaterialBlock`.
#[no_mangle]
pub unsafe extern "C" fn stoss_material_defaults_4340(
    block: *mut StossMaterialBlock,
) -> StossStatus {
    // SAFETY: caller contract on `block`.
    let body = || unsafe { write_struct(block, StossMaterialBlock::steel_4340(), "block") };
    // SAFETY: no message buffer (NULL).
    unsafe { boundary(std::ptr::null_mut(), 0, body) }
}

/// Fill `block` with RHT concrete: the 92 MPa high-performance concrete of seed 001
/// (FOI-R--0281--SE) table 4.4 (G 18.0 GPa, f'c 92 MPa, FT* 0.057, FS* 0.30, A 1.9, N 0.6,
/// Q2,0 0.6805, BQ 0.0105, PREFACT 2, TENSRAT 0.80, COMPRAT 0.75, cap on, B 1.3, M 0.65,
/// alpha 0.010, delta 0.013, D1 0.04, D2 1, EFMIN 0.01, SHRATD 0.13, hydro tensile limit),
/// rho 2420 kg/m^3, over the kernel's illustrative P-alpha EoS (docs/user-material.md),
/// isothermal, initial temperature 293 K, no erosion. Every field is written.
///
/// # Safety
/// `block` is NULL or valid for writes of one `StossMaterialBlock`.
#[no_mangle]
pub unsafe extern "C" fn stoss_material_defaults_hpc92(
    block: *mut StossMaterialBlock,
) -> StossStatus {
    // SAFETY: caller contract on `block`.
    let body = || unsafe { write_struct(block, StossMaterialBlock::concrete_hpc_92(), "block") };
    // SAFETY: no message buffer (NULL).
    unsafe { boundary(std::ptr::null_mut(), 0, body) }
}

/// Fill `block` with K&C concrete: the 100 MPa high-performance concrete of seed 001
/// (FOI-R--0281--SE) chapter 5 (tables 5.1 to 5.3: rho 2420 kg/m^3, fc 100 MPa, ft 5.2 MPa,
/// G 18.97 GPa, the meridians scaled from Malvar's 45.4 MPa set, b1 1.6, b2 1.35, the damage
/// function of table 5.3, the tabulated EoS of table 5.2), CEB-FIP rates, no crack band,
/// isothermal, initial temperature 293 K. Every field is written.
///
/// # Safety
/// `block` is NULL or valid for writes of one `StossMaterialBlock`.
#[no_mangle]
pub unsafe extern "C" fn stoss_material_defaults_kc100(
    block: *mut StossMaterialBlock,
) -> StossStatus {
    // SAFETY: caller contract on `block`.
    let body = || unsafe { write_struct(block, StossMaterialBlock::concrete_kc_100(), "block") };
    // SAFETY: no message buffer (NULL).
    unsafe { boundary(std::ptr::null_mut(), 0, body) }
}

/// Validate a material block: layout version, struct size, selectors, every constant of the
/// selected families. `STOSS_STATUS_OK`, or the status and a message naming the first
/// offending field (e.g. `strength.johnson_cook: yield_stress: must be > 0, got -1`).
///
/// # Safety
/// `block` is NULL or points to a readable, initialised `StossMaterialBlock` (at least its
/// 8-byte header if the version or size differ); `message` is NULL or valid for
/// `message_capacity` bytes.
#[no_mangle]
pub unsafe extern "C" fn stoss_material_validate(
    block: *const StossMaterialBlock,
    message: *mut c_char,
    message_capacity: usize,
) -> StossStatus {
    let body = || {
        // SAFETY: caller contract on `block`.
        let block = unsafe { read_block(block) }?;
        block.to_model().map(|_| ())
    };
    // SAFETY: caller contract on `message`.
    unsafe { boundary(message, message_capacity, body) }
}

/// The moduli a host needs for its time step, contact and hourglass stiffness (what LS-DYNA
/// reads from `cm(IBULK)`, `cm(IG)`): the bulk modulus `dp/dmu` of the EoS at the reference
/// state, the shear modulus, and the elastic longitudinal wave speed
/// `sqrt((K + 4G/3)/rho0)`. Each output pointer may be NULL.
///
/// # Safety
/// `block` as for `stoss_material_validate`; each output NULL or valid for one `double`;
/// `message` NULL or valid for `message_capacity` bytes.
#[no_mangle]
pub unsafe extern "C" fn stoss_material_elastic_moduli(
    block: *const StossMaterialBlock,
    bulk_modulus: *mut f64,
    shear_modulus: *mut f64,
    wave_speed: *mut f64,
    message: *mut c_char,
    message_capacity: usize,
) -> StossStatus {
    let body = || {
        // SAFETY: caller contract on `block`.
        let model = unsafe { read_block(block) }?.to_model()?;
        let (bulk, shear, speed) = per_family!(model, m => (
            initial_bulk_modulus(m.eos()),
            m.shear_modulus(),
            crate::adapters::elastic_wave_speed(m),
        ));
        // SAFETY: caller contract on the outputs.
        unsafe {
            write_optional(bulk_modulus, bulk, "bulk_modulus")?;
            write_optional(shear_modulus, shear, "shear_modulus")?;
            write_optional(wave_speed, speed, "wave_speed")?;
        }
        Ok(())
    };
    // SAFETY: caller contract on `message`.
    unsafe { boundary(message, message_capacity, body) }
}

/// Write the card (flat constant array for LS-DYNA `cm` / Abaqus `props`) of a valid block
/// into `card[0..capacity)`; `*length` receives the number of values used (41 plus the EoS
/// section; at most `STOSS_CARD_MAX_LENGTH`). `STOSS_STATUS_BUFFER_TOO_SMALL` (and the length
/// needed in `*length`) if `capacity` is too small. See docs/user-material.md for the slots.
///
/// # Safety
/// `block` as for `stoss_material_validate`; `card` NULL or valid for `capacity` doubles;
/// `length` NULL or valid for one `size_t`; `message` NULL or valid for `message_capacity`.
#[no_mangle]
pub unsafe extern "C" fn stoss_material_to_card(
    block: *const StossMaterialBlock,
    card: *mut f64,
    capacity: usize,
    length: *mut usize,
    message: *mut c_char,
    message_capacity: usize,
) -> StossStatus {
    let body = || {
        // SAFETY: caller contract on `block`.
        let block = unsafe { read_block(block) }?;
        let (values, used) = card_from_block(&block)?;
        // SAFETY: caller contract on `length`.
        unsafe { write_optional(length, used, "length") }?;
        if capacity < used {
            return Err(FfiError::new(
                StossStatus::BufferTooSmall,
                format!("card: capacity {capacity}, {used} values needed"),
            ));
        }
        // SAFETY: caller contract on `card` (valid for `capacity >= used` doubles).
        let mut out = unsafe { ArrayOut::new(card, capacity, "card") }?;
        for (i, value) in values[..used].iter().enumerate() {
            out.set(i, *value);
        }
        Ok(())
    };
    // SAFETY: caller contract on `message`.
    unsafe { boundary(message, message_capacity, body) }
}

/// Parse a card (`length` doubles, e.g. LS-DYNA `cm(1..lmc)`) into `block` and validate it.
/// On failure `block` is left unchanged.
///
/// # Safety
/// `card` NULL or valid for `length` doubles; `block` NULL or valid for writes of one
/// `StossMaterialBlock`; `message` NULL or valid for `message_capacity` bytes.
#[no_mangle]
pub unsafe extern "C" fn stoss_material_from_card(
    card: *const f64,
    length: usize,
    block: *mut StossMaterialBlock,
    message: *mut c_char,
    message_capacity: usize,
) -> StossStatus {
    let body = || {
        // SAFETY: caller contract on `card`.
        let values = unsafe { ArrayIn::new(card, length, "card") }?;
        let (values, used) = copy_card(&values, length);
        let parsed = block_from_card(&values[..used])?;
        parsed.to_model()?;
        // SAFETY: caller contract on `block`.
        unsafe { write_struct(block, parsed, "block") }
    };
    // SAFETY: caller contract on `message`.
    unsafe { boundary(message, message_capacity, body) }
}

/// Set `n` points to the material's initial state: zero stress, `eps_p = 0`, rate 0,
/// `T = initial_temperature`, `D = 0`, `V/V0 = 1`, `E = 0`, EoS history at its initial value
/// (P-alpha: `alpha0`), flags 0.
///
/// # Safety
/// `block` as for `stoss_material_validate`; `state` NULL or pointing to a
/// `StossBatchState` whose arrays are NULL or valid for `n` elements each; `message` NULL or
/// valid for `message_capacity` bytes.
#[no_mangle]
pub unsafe extern "C" fn stoss_state_init(
    block: *const StossMaterialBlock,
    n: usize,
    state: *const StossBatchState,
    message: *mut c_char,
    message_capacity: usize,
) -> StossStatus {
    let body = || {
        // SAFETY: caller contract on `block`.
        let block = unsafe { read_block(block) }?;
        let model = block.to_model()?;
        zero_points(n)?;
        // SAFETY: caller contract on `state` and its arrays.
        let mut views = unsafe { StateViews::new(&read_struct(state, "state")?, n) }?;
        let initial = block.initial_state(&model);
        for i in 0..n {
            views.write(i, &initial);
        }
        Ok(())
    };
    // SAFETY: caller contract on `message`.
    unsafe { boundary(message, message_capacity, body) }
}

/// Update `n` integration points over one step of `dt` seconds (structure of arrays).
///
/// `input`: strain increments (tensor shear) and optional end-of-step relative volumes;
/// `state`: the in/out history of every point; `output` (may be NULL, and each of its arrays
/// may be NULL): wave speeds, failure codes, per-point statuses, consistent tangents.
///
/// Points are updated independently, in index order. A point whose update fails keeps its
/// state unchanged and gets its status in `output->status`; the others proceed. The return
/// value is `STOSS_STATUS_OK` if every point succeeded, otherwise the status of the first
/// failing point, whose index goes to `*first_failure` (`n` if none; may be NULL) and into
/// the message (`point 17: time step dt must be > 0`).
///
/// # Safety
/// `block` as for `stoss_material_validate`; `input`, `state`, `output` NULL or pointing to
/// their structs, whose arrays are NULL or valid for `n` elements (`36 n` for the tangent);
/// `first_failure` NULL or valid for one `size_t`; `message` NULL or valid for
/// `message_capacity` bytes. Arrays may overlap (nothing is assumed about aliasing), but
/// results are then meaningless.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn stoss_update_batch(
    block: *const StossMaterialBlock,
    n: usize,
    dt: f64,
    input: *const StossBatchInput,
    state: *const StossBatchState,
    output: *const StossBatchOutput,
    first_failure: *mut usize,
    message: *mut c_char,
    message_capacity: usize,
) -> StossStatus {
    let body = || {
        // SAFETY: caller contract on `block`.
        let model = unsafe { read_block(block) }?.to_model()?;
        zero_points(n)?;
        // SAFETY: caller contract on `input` and its arrays.
        let input = unsafe { InputViews::new(&read_struct(input, "input")?, n) }?;
        // SAFETY: caller contract on `state` and its arrays.
        let mut state = unsafe { StateViews::new(&read_struct(state, "state")?, n) }?;
        let mut output = if output.is_null() {
            OutputViews::none()
        } else {
            // SAFETY: caller contract on `output` and its arrays.
            unsafe { OutputViews::new(&read_struct(output, "output")?, n) }?
        };
        check_optional_pointer(first_failure.cast_const(), "first_failure")?;
        let failure = per_family!(model, m => run_batch(m, n, dt, &input, &mut state, &mut output));
        report(n, failure, first_failure)
    };
    // SAFETY: caller contract on `message`.
    unsafe { boundary(message, message_capacity, body) }
}

/// LS-DYNA user-material convention (`umat4X` for `nlq = 1`, `umat4Xv` for a block of
/// `nlq` points), with the material given by its card `cm(1..lmc)`.
///
/// Arrays are Fortran column-major: `eps(nlq, 6)` strain increments with **engineering**
/// shear (`gamma = 2 eps`), Voigt `xx yy zz xy yz zx`; `sig(nlq, 6)` Cauchy stress in/out;
/// `hsv(nlq, nhv)` history in/out (`nhv >= STOSS_HISTORY_COUNT`, layout in
/// docs/user-material.md; zero-initialised history starts from the initial state).
/// Optional outputs (may be NULL): `failel(nlq)` failure codes (`STOSS_FAILED_ERODE` bit set:
/// LS-DYNA should delete the element), `wave_speed(nlq)`, `status(nlq)`.
/// Return value and `first_failure` as for `stoss_update_batch`; failing points keep `sig`
/// and `hsv` unchanged.
///
/// # Safety
/// `cm` valid for `lmc` doubles; `eps`, `sig` for `6 nlq`; `hsv` for `nhv nlq`; optional
/// arrays NULL or valid for `nlq` elements; `first_failure` NULL or valid for one `size_t`;
/// `message` NULL or valid for `message_capacity` bytes.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn stoss_lsdyna_umat(
    cm: *const f64,
    lmc: usize,
    nlq: usize,
    dt: f64,
    eps: *const f64,
    sig: *mut f64,
    hsv: *mut f64,
    nhv: usize,
    failel: *mut i32,
    wave_speed: *mut f64,
    status: *mut i32,
    first_failure: *mut usize,
    message: *mut c_char,
    message_capacity: usize,
) -> StossStatus {
    let body = || {
        // SAFETY: caller contract on `cm`.
        let card = unsafe { ArrayIn::new(cm, lmc, "cm") }?;
        let (card, used) = copy_card(&card, lmc);
        let block = block_from_card(&card[..used])?;
        let model = block.to_model()?;
        zero_points(nlq)?;
        if nhv < STOSS_HISTORY_COUNT {
            return Err(FfiError::new(
                StossStatus::BufferTooSmall,
                format!("nhv: {nhv} history variables, at least {STOSS_HISTORY_COUNT} needed"),
            ));
        }
        let components = product(nlq, 6, "nlq")?;
        let history = product(nlq, nhv, "nlq x nhv")?;
        // SAFETY: caller contract on every array (sizes as documented above).
        let mut arrays = unsafe {
            LsDynaArrays {
                nlq,
                nhv,
                eps: ArrayIn::new(eps, components, "eps")?,
                sig: ArrayOut::new(sig, components, "sig")?,
                hsv: ArrayOut::new(hsv, history, "hsv")?,
                failel: ArrayOut::optional(failel, nlq, "failel")?,
                wave_speed: ArrayOut::optional(wave_speed, nlq, "wave_speed")?,
                status: ArrayOut::optional(status, nlq, "status")?,
            }
        };
        let initial = block.initial_state(&model);
        let failure = per_family!(model, m => run_lsdyna(m, &initial, dt, &mut arrays));
        report(nlq, failure, first_failure)
    };
    // SAFETY: caller contract on `message`.
    unsafe { boundary(message, message_capacity, body) }
}

/// Abaqus/Explicit VUMAT convention for a block of `nblock` points, with the material given
/// by its card `props(1..nprops)`.
///
/// Arrays are Fortran column-major: `strain_inc(nblock, ndir+nshr)` (**tensor** shear, the
/// VUMAT convention), `stress_old/new(nblock, ndir+nshr)`, `state_old/new(nblock, nstatev)`,
/// `ener_intern_old/new(nblock)`. Components are Abaqus/Explicit's `11 22 33 12 23 31`
/// (`ndir = 3`, `nshr = 3`) or `11 22 33 12` (`nshr = 1`: plane strain, axisymmetric).
/// `nstatev >= STOSS_HISTORY_COUNT`; state variables beyond those are copied old to new.
/// `ener_intern_new` is the internal energy per unit **mass** (J/kg): stoss's energy per
/// unit reference volume divided by the reference density; `ener_intern_old` is only read
/// by the data-check call. When `total_time == 0` and `step_time == 0` (Abaqus's data-check
/// call with fictitious strains) the response is elastic and no history is advanced.
/// Optional outputs (may be NULL): `wave_speed(nblock)`, `status(nblock)`. Failing points
/// get new = old. Return value and `first_failure` as for `stoss_update_batch`.
///
/// # Safety
/// `props` valid for `nprops` doubles; the strain and stress arrays for
/// `(ndir + nshr) nblock`, state arrays for `nstatev nblock`, energy arrays and optional
/// outputs for `nblock` elements; `first_failure` NULL or valid for one `size_t`; `message`
/// NULL or valid for `message_capacity` bytes. New arrays may be the old arrays.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn stoss_abaqus_vumat(
    props: *const f64,
    nprops: usize,
    nblock: usize,
    ndir: usize,
    nshr: usize,
    nstatev: usize,
    step_time: f64,
    total_time: f64,
    dt: f64,
    strain_inc: *const f64,
    stress_old: *const f64,
    state_old: *const f64,
    ener_intern_old: *const f64,
    stress_new: *mut f64,
    state_new: *mut f64,
    ener_intern_new: *mut f64,
    wave_speed: *mut f64,
    status: *mut i32,
    first_failure: *mut usize,
    message: *mut c_char,
    message_capacity: usize,
) -> StossStatus {
    let body = || {
        // SAFETY: caller contract on `props`.
        let card = unsafe { ArrayIn::new(props, nprops, "props") }?;
        let (card, used) = copy_card(&card, nprops);
        let block = block_from_card(&card[..used])?;
        let model = block.to_model()?;
        zero_points(nblock)?;
        if ndir != 3 || !(nshr == 1 || nshr == 3) {
            return Err(FfiError::new(
                StossStatus::InvalidArgument,
                format!(
                    "ndir, nshr: ({ndir}, {nshr}) not supported; 3D (3, 3) or plane \
                         strain/axisymmetric (3, 1)"
                ),
            ));
        }
        if nstatev < STOSS_HISTORY_COUNT {
            return Err(FfiError::new(
                StossStatus::BufferTooSmall,
                format!(
                    "nstatev: {nstatev} state variables, at least {STOSS_HISTORY_COUNT} \
                         needed"
                ),
            ));
        }
        let components = product(nblock, ndir + nshr, "nblock x (ndir + nshr)")?;
        let states = product(nblock, nstatev, "nblock x nstatev")?;
        // SAFETY: caller contract on every array (sizes as documented above).
        let mut arrays = unsafe {
            VumatArrays {
                nblock,
                nshr,
                nstatev,
                strain_inc: ArrayIn::new(strain_inc, components, "strain_inc")?,
                stress_old: ArrayIn::new(stress_old, components, "stress_old")?,
                state_old: ArrayIn::new(state_old, states, "state_old")?,
                ener_intern_old: ArrayIn::new(ener_intern_old, nblock, "ener_intern_old")?,
                stress_new: ArrayOut::new(stress_new, components, "stress_new")?,
                state_new: ArrayOut::new(state_new, states, "state_new")?,
                ener_intern_new: ArrayOut::new(ener_intern_new, nblock, "ener_intern_new")?,
                wave_speed: ArrayOut::optional(wave_speed, nblock, "wave_speed")?,
                status: ArrayOut::optional(status, nblock, "status")?,
            }
        };
        let data_check = total_time == 0.0 && step_time == 0.0;
        let initial = block.initial_state(&model);
        let failure = per_family!(model, m => run_vumat(m, &initial, dt, data_check, &mut arrays));
        report(nblock, failure, first_failure)
    };
    // SAFETY: caller contract on `message`.
    unsafe { boundary(message, message_capacity, body) }
}
