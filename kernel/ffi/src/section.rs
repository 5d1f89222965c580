//! A family's scalar constants in the block and on the card, read from the kernel's
//! descriptor ([`stoss_kernel::parameters`]) instead of copied field by field.
//!
//! Two section forms exist:
//! - **Array sections** (K&C, [`crate::block::StossKc`]): the described constants in the
//!   descriptor's order, except those the block keeps in its common fields ([`COMMON`]: the
//!   shear modulus is the block's `shear_modulus`, card P3). The kernel model gives and takes
//!   them by index ([`Constants::slot`]); the card holds them in the same order. Adding a
//!   constant to such a family is one edit of the kernel's family file.
//! - **Named sections** (the J2 families and RHT): `#[repr(C)]` structs whose doubles are
//!   public C ABI in an order fixed when the family entered the block (layout versions 1 to
//!   3), which for MJC and TJC is not the descriptor's. [`DescribedSection`] names those
//!   doubles once, in ABI order ([`described_section!`]); compile-time assertions prove the
//!   names are the struct's fields at their offsets and are exactly the family's described
//!   constants. Block, export and card then copy by name ([`to_model`], [`from_model`]) or as
//!   one slice in ABI order ([`DescribedSection::constants`]): a constant added to such a
//!   family fails to compile until the section gains its field (a layout change, as a public
//!   struct's must be).

use stoss_kernel::parameters::{Constants, Parameter};

/// Described constants the block holds in its common fields rather than in a family's section.
pub const COMMON: [&str; 1] = ["shear_modulus"];

/// A `#[repr(C)]` block section whose trailing doubles are a family's described constants,
/// named in ABI order. Implemented by [`described_section!`], which checks the layout.
pub trait DescribedSection {
    /// The kernel model whose descriptor names the section's constants.
    type Model: Constants;
    /// The section's doubles, by their field (and descriptor) names, in ABI order.
    const FIELDS: &'static [&'static str];
    /// The descriptor index of each of [`DescribedSection::FIELDS`] (found at compile time).
    const INDICES: &'static [usize];

    /// The section's constants in ABI order.
    fn constants(&self) -> &[f64];

    /// The section's constants in ABI order, mutably.
    fn constants_mut(&mut self) -> &mut [f64];
}

/// `base` with every constant of `section` written in by name; fields the descriptor does not
/// cover (options, the shear modulus) keep `base`'s values.
pub fn to_model<S: DescribedSection>(section: &S, mut base: S::Model) -> S::Model {
    for (&index, value) in S::INDICES.iter().zip(section.constants()) {
        // Every index is a described constant of `S::Model` (found at compile time by
        // `described_section!`), so the write cannot miss.
        if let Some(slot) = base.slot(index) {
            *slot = *value;
        }
    }
    base
}

/// Write the constants of `model` into `section` by name (through their descriptor indices).
pub fn from_model<S: DescribedSection>(model: &mut S::Model, section: &mut S) {
    for (&index, out) in S::INDICES.iter().zip(section.constants_mut()) {
        if let Some(value) = model.slot(index) {
            *out = *value;
        }
    }
}

/// Index of the constant `name` in `parameters`; fails to compile (in a const context) if
/// there is none.
pub const fn descriptor_index(parameters: &'static [Parameter], name: &str) -> usize {
    let mut i = 0;
    while i < parameters.len() {
        if str_eq(parameters[i].name, name) {
            return i;
        }
        i += 1;
    }
    panic!("a section field is not a described constant of its model");
}

/// Implement [`DescribedSection`] for a `#[repr(C)]` struct whose fields from `first` to its
/// end are `f64` constants of `model` (a [`Constants`] type with `PARAMETERS`):
/// `described_section!(Section, Model, [first, second, ...])`.
///
/// Checked at compile time: the listed fields are contiguous doubles at increasing offsets
/// that end the struct; they are distinct, each a described constant of the model outside
/// [`COMMON`], and as many as the model's section constants ([`section_length`]), so the list
/// is exactly the model's section constants in some order.
#[macro_export]
macro_rules! described_section {
    ($section:ty, $model:ty, [$first:ident $(, $field:ident)* $(,)?]) => {
        impl $crate::section::DescribedSection for $section {
            type Model = $model;
            const FIELDS: &'static [&'static str] = &[stringify!($first) $(, stringify!($field))*];
            const INDICES: &'static [usize] = &[
                $crate::section::descriptor_index(<$model>::PARAMETERS, stringify!($first))
                $(, $crate::section::descriptor_index(<$model>::PARAMETERS, stringify!($field)))*
            ];

            fn constants(&self) -> &[f64] {
                let first = std::mem::offset_of!($section, $first);
                let base = std::ptr::from_ref(self).cast::<u8>();
                // SAFETY: the const block below proves that `$section` is `#[repr(C)]`-laid
                // out with `FIELDS.len()` `f64` fields from byte offset `first` (a multiple of
                // 8) to its end, with no padding between them; the pointer is derived from the
                // whole borrowed struct, so the slice is initialised, aligned and lives as long
                // as `self`'s borrow.
                unsafe {
                    std::slice::from_raw_parts(base.add(first).cast::<f64>(), Self::FIELDS.len())
                }
            }

            fn constants_mut(&mut self) -> &mut [f64] {
                let first = std::mem::offset_of!($section, $first);
                let base = std::ptr::from_mut(self).cast::<u8>();
                // SAFETY: as in `constants`; the borrow is unique because `self` is.
                unsafe {
                    std::slice::from_raw_parts_mut(
                        base.add(first).cast::<f64>(),
                        Self::FIELDS.len(),
                    )
                }
            }
        }

        const _: () = {
            const FIELDS: &[&str] = <$section as $crate::section::DescribedSection>::FIELDS;
            const FIRST: usize = std::mem::offset_of!($section, $first);
            assert!(FIRST % std::mem::align_of::<f64>() == 0);
            assert!(std::mem::align_of::<$section>() >= std::mem::align_of::<f64>());
            assert!(std::mem::size_of::<$section>() == FIRST + 8 * FIELDS.len());
            let mut _index = 0;
            $(
                _index += 1;
                assert!(std::mem::offset_of!($section, $field) == FIRST + 8 * _index);
            )*
            assert!(
                FIELDS.len()
                    == $crate::section::section_length(<$model>::PARAMETERS)
            );
            let mut i = 0;
            while i < FIELDS.len() {
                assert!($crate::section::is_section_constant(<$model>::PARAMETERS, FIELDS[i]));
                let mut j = i + 1;
                while j < FIELDS.len() {
                    assert!(!$crate::section::str_eq(FIELDS[i], FIELDS[j]));
                    j += 1;
                }
                i += 1;
            }
        };
    };
}

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

/// Whether `name` is a described constant of `parameters` that a section holds.
pub const fn is_section_constant(parameters: &'static [Parameter], name: &str) -> bool {
    if is_common(name) {
        return false;
    }
    let mut i = 0;
    while i < parameters.len() {
        if str_eq(parameters[i].name, name) {
            return true;
        }
        i += 1;
    }
    false
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

/// Byte-wise string equality in a const context.
pub const fn str_eq(a: &str, b: &str) -> bool {
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
