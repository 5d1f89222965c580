/* Host smoke test for the no_std static library: link it into a plain C program (no Rust
 * runtime, no std) and check the 4340 uniaxial-stress result is plausible. Built and run by
 * .ci/nostd.sh when a C compiler is available. */
#include <stdio.h>

double stoss_no_std_link_jc_uniaxial_stress(double final_strain, double strain_rate,
                                            unsigned int steps);

/* The precompiled x86_64 `core` carries unwind tables that name `rust_eh_personality`,
 * normally supplied by `std`. Nothing unwinds here (panic = "abort", and the library's
 * panic handler never returns), so an empty definition satisfies the linker and is never
 * called. */
void rust_eh_personality(void);
void rust_eh_personality(void) {}

int main(void) {
    /* JC 4340 at eps ~ 0.1, 1000 /s: (792 + 510 * 0.1^0.26) MPa * (1 + 0.014 ln 1000),
     * slightly thermally softened: about 1.15 GPa. */
    double stress = stoss_no_std_link_jc_uniaxial_stress(0.1, 1000.0, 200u);
    printf("4340 uniaxial stress at log strain 0.1, 1000 /s: %.6e Pa\n", stress);
    if (!(stress > 1.0e9 && stress < 1.3e9)) {
        fprintf(stderr, "implausible stress\n");
        return 1;
    }
    return 0;
}
