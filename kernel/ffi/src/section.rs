//! A family's scalar constants in the block and on the card, read from the kernel's
//! descriptor ([`stoss_kernel::parameters`]) instead of copied field by field.
//!
//! A block section holds the family's described constants in the descriptor's order, except
//! those the block keeps in its common fields ([`COMMON`]: the shear modulus is the block's
//! `shear_modulus`, card P3). The kernel model gives and takes them by index
//! ([`Constants::slot`]); the card holds them in the same order. Adding a constant to a family
//! that is written this way (K&C, [`crate::block::StossKc`]) is then one edit of the kernel's
//! family file.
//!
//! RHT concrete's section ([`crate::block::StossRht`], layout 3) has named fields; they are
//! the descriptor's constants in its order (checked against the generated header by
//! `tests/abi.rs`), so RHT reads them through the same view ([`rht_constants`]).

use stoss_kernel::parameters::{Constants, Parameter};

use crate::block::StossRht;

/// Described constants the block holds in its common fields rather than in a family's section.
pub const COMMON: [&str; 1] = ["shear_modulus"];

/// The described constants of `parameters` a block section holds, in order (those not in
/// [`COMMON`]).
pub fn section_parameters(
    parameters: &'static [Parameter],
) -> impl Iterator<Item = (usize, &'static Parameter)> {
    parameters
        .iter()
        .enumerate()
        .filter(|(_, parameter)| !COMMON.contains(&parameter.name))
}

/// Number of described constants of `parameters` a block section holds.
pub const fn section_length(parameters: &'static [Parameter]) -> usize {
    let mut count = 0;
    let mut i = 0;
    while i < parameters.len() {
        if !is_common(parameters[i].name) {
            count += 1;
        }
        i += 1;
    }
    count
}

const fn is_common(name: &str) -> bool {
    let mut c = 0;
    while c < COMMON.len() {
        if str_eq(COMMON[c], name) {
            return true;
        }
        c += 1;
    }
    false
}

const fn str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// Write the section constants of `model` to `section` (the first
/// [`section_length`] values; the rest are left as they are).
pub fn write_section<M: Constants>(model: &mut M, section: &mut [f64]) {
    let parameters = model.parameters();
    for (slot, (index, _)) in section_parameters(parameters).enumerate() {
        if let (Some(value), Some(out)) = (model.slot(index), section.get_mut(slot)) {
            *out = *value;
        }
    }
}

/// Set the section constants of `model` from `section`, in the order of
/// [`section_parameters`].
pub fn read_section<M: Constants>(model: &mut M, section: &[f64]) {
    let parameters = model.parameters();
    for (slot, (index, _)) in section_parameters(parameters).enumerate() {
        if let (Some(value), Some(input)) = (model.slot(index), section.get(slot)) {
            *value = *input;
        }
    }
}

/// Number of floating-point constants of [`StossRht`] (the RHT descriptor without the shear
/// modulus).
pub const RHT_CONSTANTS: usize = section_length(stoss_kernel::rht::RhtParameters::PARAMETERS);

const RHT_FIRST: usize = std::mem::offset_of!(StossRht, compressive_strength);

// The RHT section's doubles are contiguous, from `compressive_strength` to the end of the
// struct, and there are as many as the descriptor has section constants.
const _: () = assert!(std::mem::size_of::<StossRht>() == RHT_FIRST + 8 * RHT_CONSTANTS);
const _: () = assert!(std::mem::align_of::<StossRht>() == std::mem::align_of::<f64>());
const _: () = assert!(RHT_FIRST % std::mem::align_of::<f64>() == 0);

/// The floating-point constants of an RHT section, in the descriptor's order.
pub fn rht_constants(section: &StossRht) -> &[f64; RHT_CONSTANTS] {
    let base = std::ptr::from_ref(section).cast::<u8>();
    // SAFETY: `StossRht` is `#[repr(C)]`; from byte offset `RHT_FIRST` (a multiple of 8) to
    // its end it holds only `f64` fields, `RHT_CONSTANTS` of them with no padding between
    // (the size assertion above), so the bytes are `RHT_CONSTANTS` initialised, aligned
    // `f64`s inside the borrowed struct; the pointer is derived from the whole struct, and the
    // returned borrow lives as long as `section`'s.
    unsafe { &*base.add(RHT_FIRST).cast::<[f64; RHT_CONSTANTS]>() }
}

/// The floating-point constants of an RHT section, mutably, in the descriptor's order.
pub fn rht_constants_mut(section: &mut StossRht) -> &mut [f64; RHT_CONSTANTS] {
    let base = std::ptr::from_mut(section).cast::<u8>();
    // SAFETY: as in `rht_constants`; the borrow is unique because `section` is.
    unsafe { &mut *base.add(RHT_FIRST).cast::<[f64; RHT_CONSTANTS]>() }
}
