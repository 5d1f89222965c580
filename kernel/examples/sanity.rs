use stoss_kernel::drivers::*;
use stoss_kernel::*;
fn main() {
    for treatment in [RateTreatment::Implicit, RateTreatment::Lagged] {
        for rate in [1.0, 10.0, 100.0, 1000.0] {
            let mut m = Material::STEEL_4340;
            m.heating = Heating::Isothermal;
            m.rate_treatment = treatment;
            let mut st = MaterialState::initial(298.0);
            let mut sink = LastRecord::default();
            uniaxial_stress(
                &m,
                &mut st,
                &UniaxialStressLoading {
                    strain_rate: rate,
                    final_strain: 0.1,
                    steps: 5000,
                },
                &mut sink,
            )
            .unwrap();
            let r = sink.last.unwrap();
            let ana = m.strength.flow_stress(r.plastic_strain, rate, 298.0).value;
            println!("{:?} {rate:6} sxx {:.4e} syy {:.2e} eps_p {:.5} rate_p {:.3e} analytical {:.4e} rel {:.3e}", treatment, r.stress[0], r.stress[1], r.plastic_strain, r.plastic_strain_rate, ana, r.stress[0]/ana-1.0);
        }
    }
}
