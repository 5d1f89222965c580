//! Blast loads on structures.
//!
//! - [`euler`]: a 2D (planar or axisymmetric) second-order Godunov solver for detonation
//!   products and air, with programmed burn, that records the pressure on a rigid wall;
//! - [`fluid`]: the JWL products / ideal-gas air mixture it uses;
//! - [`record`]: the wall's pressure records formed from its steps.

pub mod cache;
pub mod euler;
pub mod fluid;
pub mod kingery_bulmash;
pub mod near_field;
pub mod record;
