//! One description per model constant (after MFront/MGIS): its name, symbol, SI unit and
//! default search range, and access to its value by index. Every interface reads it: the
//! material file keys (the name is the struct field and TOML key), a calibration's search
//! space and its default bounds, the diagnosis' fitted constants, the reports and cards.
//!
//! A model implements [`Constants`] with [`struct_constants!`](crate::struct_constants) (a
//! parameter struct) or [`enum_constants!`](crate::enum_constants) (a term enum, whose
//! constants depend on its variant). Both macros take the field list once and derive the
//! names from the field identifiers, so a description and the value it reads cannot drift
//! apart.

/// Description of one model constant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parameter {
    /// Field name in the parameter struct or term variant, and the material file's key.
    pub name: &'static str,
    /// The symbol in the model's equation (`A`, `n`, `C1`, ...).
    pub symbol: &'static str,
    /// SI unit (`Pa`, `-`, `1/s`, `K`, `1/K`).
    pub unit: &'static str,
    /// Default search range of a calibration (seed 000 section 4.1 where it gives one);
    /// `None` for a constant held by convention (reference rates and temperatures, the
    /// melting temperature), which a user may still fit with explicit bounds.
    pub search: Option<(f64, f64)>,
}

/// A model whose constants are described by [`Parameter`]s and addressable by index.
pub trait Constants {
    /// The constants of this model (of its variant, for a term enum), in order.
    fn parameters(&self) -> &'static [Parameter];

    /// The constant at `index` of [`Constants::parameters`], mutably; `None` past the end.
    fn slot(&mut self, index: usize) -> Option<&mut f64>;

    /// Index of the constant named `name`.
    fn index_of(&self, name: &str) -> Option<usize> {
        self.parameters().iter().position(|p| p.name == name)
    }

    /// The constant named `name`, mutably.
    fn named_slot(&mut self, name: &str) -> Option<&mut f64> {
        let index = self.index_of(name)?;
        self.slot(index)
    }

    /// Value of the constant named `name`.
    fn get(&self, name: &str) -> Option<f64>
    where
        Self: Copy,
    {
        let mut copy = *self;
        copy.named_slot(name).map(|value| *value)
    }

    /// Set the constant named `name`; `None` if the model has no such constant.
    fn set(&mut self, name: &str, value: f64) -> Option<()> {
        *self.named_slot(name)? = value;
        Some(())
    }
}

/// A composite model (an EoS family, a composed strength, a material file's strength) whose
/// constants are addressed by a path (`term.name`, or the constant's name in the family of
/// the variant): the counterpart of [`Constants`] for models built from described parts.
pub trait ConstantPaths {
    /// The constant at `path`, mutably; `None` if there is none.
    fn slot(&mut self, path: &str) -> Option<&mut f64>;

    /// Value of the constant at `path`.
    fn get(&self, path: &str) -> Option<f64>
    where
        Self: Clone,
    {
        let mut copy = self.clone();
        copy.slot(path).map(|value| *value)
    }

    /// Set the constant at `path`; `None` if there is none.
    fn set(&mut self, path: &str, value: f64) -> Option<()> {
        *self.slot(path)? = value;
        Some(())
    }
}

/// Implement [`Constants`] for a struct of `f64` constants, with the descriptions also as the
/// associated constant `PARAMETERS`:
/// `struct_constants!(Type, [field = ("symbol", "unit", search), ...])`.
#[macro_export]
macro_rules! struct_constants {
    ($ty:ty, [$($field:ident = ($symbol:literal, $unit:literal, $search:expr)),* $(,)?]) => {
        impl $ty {
            /// The descriptions of this model's constants
            /// ([`Constants::parameters`](crate::parameters::Constants::parameters)).
            pub const PARAMETERS: &'static [$crate::parameters::Parameter] = &[$(
                $crate::parameters::Parameter {
                    name: stringify!($field),
                    symbol: $symbol,
                    unit: $unit,
                    search: $search,
                }
            ),*];
        }

        impl $crate::parameters::Constants for $ty {
            fn parameters(&self) -> &'static [$crate::parameters::Parameter] {
                Self::PARAMETERS
            }

            fn slot(&mut self, index: usize) -> Option<&mut f64> {
                [$(&mut self.$field),*].into_iter().nth(index)
            }
        }
    };
}

/// Implement [`Constants`] for an enum whose variants hold `f64` constants (unit variants
/// are written `Variant {}`):
/// `enum_constants!(Type, { Variant { field = ("symbol", "unit", search), ... }, ... })`.
#[macro_export]
macro_rules! enum_constants {
    ($ty:ident, {$($variant:ident {$($field:ident = ($symbol:literal, $unit:literal, $search:expr)),* $(,)?}),* $(,)?}) => {
        impl $ty {
            /// The descriptions of every variant's constants, in declaration order (what
            /// [`Constants::parameters`](crate::parameters::Constants::parameters) gives for
            /// each variant).
            pub const VARIANT_PARAMETERS: &'static [&'static [$crate::parameters::Parameter]] = &[$(
                &[$(
                    $crate::parameters::Parameter {
                        name: stringify!($field),
                        symbol: $symbol,
                        unit: $unit,
                        search: $search,
                    }
                ),*]
            ),*];
        }

        impl $crate::parameters::Constants for $ty {
            fn parameters(&self) -> &'static [$crate::parameters::Parameter] {
                match self {$(
                    $ty::$variant { .. } => {
                        const PARAMETERS: &[$crate::parameters::Parameter] = &[$(
                            $crate::parameters::Parameter {
                                name: stringify!($field),
                                symbol: $symbol,
                                unit: $unit,
                                search: $search,
                            }
                        ),*];
                        PARAMETERS
                    }
                )*}
            }

            fn slot(&mut self, index: usize) -> Option<&mut f64> {
                match self {$(
                    $ty::$variant { $($field),* } => [$($field),*].into_iter().nth(index),
                )*}
            }
        }
    };
}

/// The parameter named `name` in `parameters`.
pub fn find<'a>(parameters: &'a [Parameter], name: &str) -> Option<&'a Parameter> {
    parameters.iter().find(|p| p.name == name)
}

/// Search range of a stress constant: `[0, 3 GPa]` (seed 000 section 4.1).
pub const STRESS: Option<(f64, f64)> = Some((0.0, 3.0e9));
/// Search range of a hardening exponent: `[0, 1]` (seed 000 section 4.1).
pub const HARDENING_EXPONENT: Option<(f64, f64)> = Some((0.0, 1.0));
/// Search range of a Voce saturation rate: `[0, 2000]`.
pub const SATURATION_RATE: Option<(f64, f64)> = Some((0.0, 2000.0));
/// Search range of a rate sensitivity or rate exponent: `[0, 0.1]` (seed 000 section 4.1).
pub const RATE_SENSITIVITY: Option<(f64, f64)> = Some((0.0, 0.1));
/// Search range of the thermal-softening exponent: `[0.5, 1.5]` (seed 000 section 4.1).
pub const THERMAL_EXPONENT: Option<(f64, f64)> = Some((0.5, 1.5));
/// Search range of a thermal drop's strength fraction: `[0, 0.9]`.
pub const THERMAL_DROP: Option<(f64, f64)> = Some((0.0, 0.9));
/// A constant held by convention (no default search range).
pub const FIXED: Option<(f64, f64)> = None;
