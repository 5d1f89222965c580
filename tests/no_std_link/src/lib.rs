//! no_std link proof for stoss-kernel.
//!
//! This static library has no `std`, its own panic handler and one C-callable export that
//! runs the Johnson-Cook 4340 uniaxial-stress driver, so the kernel's update, return mapping,
//! consistent tangent and driver code are all linked in. Any `std` reaching the dependency
//! graph would make the build fail with a duplicate `panic_impl` lang item.
//!
//! There is no `unsafe` block here. (`#[no_mangle]` is a plain attribute in edition 2021.)
#![no_std]
#![no_main]

use core::panic::PanicInfo;

use stoss_kernel::drivers::{uniaxial_stress, LastRecord, UniaxialStressLoading};
use stoss_kernel::{Material, MaterialState};

/// Drive 4340 steel (Johnson & Cook 1985) in uniaxial stress from 298 K to axial log strain
/// `final_strain` at axial rate `strain_rate` (1/s) in `steps` steps. Returns the final axial
/// stress (Pa), or NaN if the driver reports an error or records nothing.
#[no_mangle]
pub extern "C" fn stoss_no_std_link_jc_uniaxial_stress(
    final_strain: f64,
    strain_rate: f64,
    steps: u32,
) -> f64 {
    let mut state = MaterialState::initial(298.0);
    let loading = UniaxialStressLoading {
        strain_rate,
        final_strain,
        steps,
    };
    let mut sink = LastRecord::default();
    match uniaxial_stress(&Material::STEEL_4340, &mut state, &loading, &mut sink) {
        Ok(()) => sink.last.map_or(f64::NAN, |record| record.stress[0]),
        Err(_) => f64::NAN,
    }
}

/// Without `std` there is nothing to unwind into or report to: stop here.
#[panic_handler]
fn panic(_info: &PanicInfo) -> ! {
    loop {
        core::hint::spin_loop();
    }
}
