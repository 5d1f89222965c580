/*
 * C link test of the stoss C ABI: drives uniaxial-strain paths through the batch interface
 * (stoss_update_batch) and the Abaqus VUMAT adapter (stoss_abaqus_vumat), and writes each
 * point's history as hex bit patterns, one line per step:
 *
 *   time strain(6) stress(6) eps_p rate T D E wave_speed flags
 *
 * The same cases are written by the Rust reference (kernel/ffi/examples/reference_histories.rs,
 * kernel drivers, no ABI); .ci/ffi.sh compares the files byte for byte.
 *
 * Usage: uniaxial_strain <output directory>. Exit status 0 on success.
 * Build: cc -std=c11 -ffp-contract=off -I kernel/ffi/include uniaxial_strain.c \
 *            -L<lib> -lstoss_kernel <native libs>
 */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stoss_kernel.h"

#define MESSAGE_CAPACITY 256

static const char *output_directory;

static void fail(const char *what, StossStatus status, const char *message) {
    fprintf(stderr, "uniaxial_strain: %s: %s (%d): %s\n", what, stoss_status_name(status),
            (int)status, message);
    exit(1);
}

static uint64_t bits(double value) {
    uint64_t pattern;
    memcpy(&pattern, &value, sizeof pattern);
    return pattern;
}

static FILE *open_history(const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.hex", output_directory, name);
    FILE *file = fopen(path, "w");
    if (file == NULL) {
        perror(path);
        exit(1);
    }
    return file;
}

/* One record line: the 20 values in the order of the Rust reference. */
static void write_record(FILE *file, const double values[20]) {
    for (int k = 0; k < 20; ++k) {
        fprintf(file, "%016" PRIx64 "%s", bits(values[k]), k == 19 ? "\n" : " ");
    }
}

/* Structure-of-arrays storage for up to 2 points. */
enum { MAX_POINTS = 2 };

typedef struct Points {
    double strain[6][MAX_POINTS];
    double stress[6][MAX_POINTS];
    double plastic_strain[MAX_POINTS], plastic_strain_rate[MAX_POINTS];
    double temperature[MAX_POINTS], damage[MAX_POINTS], relative_volume[MAX_POINTS];
    double internal_energy[MAX_POINTS], eos_history[MAX_POINTS];
    uint32_t flags[MAX_POINTS];
    double wave_speed[MAX_POINTS];
    int32_t failed[MAX_POINTS], status[MAX_POINTS];
} Points;

static StossBatchState state_of(Points *p) {
    StossBatchState state;
    for (int k = 0; k < 6; ++k) {
        state.stress[k] = p->stress[k];
    }
    state.plastic_strain = p->plastic_strain;
    state.plastic_strain_rate = p->plastic_strain_rate;
    state.temperature = p->temperature;
    state.damage = p->damage;
    state.relative_volume = p->relative_volume;
    state.internal_energy = p->internal_energy;
    state.eos_history = p->eos_history;
    state.flags = p->flags;
    return state;
}

/*
 * Uniaxial strain through the batch interface: point i follows final_strain[i] in `steps`
 * equal steps at axial rate `rate` (every point has the same |increment|, so one dt).
 */
static void batch_case(const StossMaterialBlock *block, size_t n, const double *final_strain,
                       unsigned steps, double rate, const char *const *names) {
    char message[MESSAGE_CAPACITY];
    Points p;
    memset(&p, 0, sizeof p);
    StossBatchState state = state_of(&p);
    StossStatus status = stoss_state_init(block, n, &state, message, sizeof message);
    if (status != STOSS_STATUS_OK) {
        fail("stoss_state_init", status, message);
    }
    double increment[MAX_POINTS], total[MAX_POINTS][6];
    FILE *files[MAX_POINTS];
    for (size_t i = 0; i < n; ++i) {
        increment[i] = final_strain[i] / (double)steps;
        memset(total[i], 0, sizeof total[i]);
        files[i] = open_history(names[i]);
    }
    const double dt = fabs(increment[0]) / rate;
    StossBatchInput input;
    for (int k = 0; k < 6; ++k) {
        input.strain_increment[k] = p.strain[k];
    }
    input.relative_volume = NULL; /* V1 = V0 exp(tr deps), as the Rust drivers */
    StossBatchOutput output = {p.wave_speed, p.failed, p.status, NULL};
    double time = 0.0;
    for (unsigned step = 0; step < steps; ++step) {
        for (size_t i = 0; i < n; ++i) {
            p.strain[0][i] = increment[i];
        }
        size_t first_failure = 0;
        status = stoss_update_batch(block, n, dt, &input, &state, &output, &first_failure,
                                    message, sizeof message);
        if (status != STOSS_STATUS_OK) {
            fail("stoss_update_batch", status, message);
        }
        if (first_failure != n) {
            fail("first_failure should be n", status, message);
        }
        time += dt;
        for (size_t i = 0; i < n; ++i) {
            for (int k = 0; k < 6; ++k) {
                total[i][k] += p.strain[k][i];
            }
            const double values[20] = {
                time, total[i][0], total[i][1], total[i][2], total[i][3], total[i][4],
                total[i][5], p.stress[0][i], p.stress[1][i], p.stress[2][i], p.stress[3][i],
                p.stress[4][i], p.stress[5][i], p.plastic_strain[i], p.plastic_strain_rate[i],
                p.temperature[i], p.damage[i], p.internal_energy[i], p.wave_speed[i],
                (double)p.flags[i]};
            write_record(files[i], values);
        }
    }
    for (size_t i = 0; i < n; ++i) {
        fclose(files[i]);
    }
}

/*
 * Uniaxial strain through the VUMAT adapter, nblock = 2, 3D (ndir = nshr = 3), arrays
 * column-major as Abaqus passes them, after Abaqus's data-check call.
 */
static void vumat_case(const StossMaterialBlock *block) {
    enum { NBLOCK = 2, NCOMP = 6, NSTATEV = 10 };
    const double final_strain[NBLOCK] = {-0.2, 0.2};
    const char *const names[NBLOCK] = {"vumat_za_compression", "vumat_za_tension"};
    const unsigned steps = 200;
    const double rate = 1.0e3;
    char message[MESSAGE_CAPACITY];
    double props[STOSS_CARD_MAX_LENGTH];
    size_t nprops = 0;
    StossStatus status = stoss_material_to_card(block, props, STOSS_CARD_MAX_LENGTH, &nprops,
                                                message, sizeof message);
    if (status != STOSS_STATUS_OK) {
        fail("stoss_material_to_card", status, message);
    }
    double strain_inc[NCOMP * NBLOCK] = {0}, stress_old[NCOMP * NBLOCK] = {0};
    double stress_new[NCOMP * NBLOCK] = {0}, state_old[NSTATEV * NBLOCK] = {0};
    double state_new[NSTATEV * NBLOCK] = {0}, energy_old[NBLOCK] = {0}, energy_new[NBLOCK];
    double wave_speed[NBLOCK];
    int32_t point_status[NBLOCK];
    size_t first_failure;
    /* The host's own state variables 9 and 10 must survive. */
    for (int i = 0; i < NBLOCK; ++i) {
        state_old[i + NBLOCK * 8] = 42.0 + i;
        state_old[i + NBLOCK * 9] = -7.0;
    }

    /* Data check: totalTime = stepTime = 0, fictitious strain; elastic, nothing kept. */
    double fictitious[NCOMP * NBLOCK] = {0};
    fictitious[0] = 1e-6;
    fictitious[1] = 1e-6;
    status = stoss_abaqus_vumat(props, nprops, NBLOCK, 3, 3, NSTATEV, 0.0, 0.0, 0.0,
                                fictitious, stress_old, state_old, energy_old, stress_new,
                                state_new, energy_new, wave_speed, point_status, &first_failure,
                                message, sizeof message);
    if (status != STOSS_STATUS_OK || !(stress_new[0] > 0.0)) {
        fail("vumat data check", status, message);
    }

    /* The same points updated in place (stressNew = stressOld etc., which the documentation
     * allows): must give the same bits as separate old and new arrays. */
    double stress_alias[NCOMP * NBLOCK], state_alias[NSTATEV * NBLOCK], energy_alias[NBLOCK];
    memcpy(stress_alias, stress_old, sizeof stress_alias);
    memcpy(state_alias, state_old, sizeof state_alias);
    memcpy(energy_alias, energy_old, sizeof energy_alias);

    double increment[NBLOCK], total[NBLOCK] = {0.0, 0.0};
    FILE *files[NBLOCK];
    for (int i = 0; i < NBLOCK; ++i) {
        increment[i] = final_strain[i] / (double)steps;
        files[i] = open_history(names[i]);
    }
    const double dt = fabs(increment[0]) / rate;
    double time = 0.0;
    for (unsigned step = 0; step < steps; ++step) {
        for (int i = 0; i < NBLOCK; ++i) {
            strain_inc[i] = increment[i]; /* component 11 of point i */
        }
        /* Abaqus's stepTime/totalTime are only both zero in the data-check call. */
        status = stoss_abaqus_vumat(props, nprops, NBLOCK, 3, 3, NSTATEV, time + dt, time + dt, dt,
                                    strain_inc, stress_old, state_old, energy_old, stress_new,
                                    state_new, energy_new, wave_speed, point_status,
                                    &first_failure, message, sizeof message);
        if (status != STOSS_STATUS_OK) {
            fail("stoss_abaqus_vumat", status, message);
        }
        status = stoss_abaqus_vumat(props, nprops, NBLOCK, 3, 3, NSTATEV, time + dt, time + dt, dt,
                                    strain_inc, stress_alias, state_alias, energy_alias,
                                    stress_alias, state_alias, energy_alias, NULL, NULL, NULL,
                                    message, sizeof message);
        if (status != STOSS_STATUS_OK) {
            fail("stoss_abaqus_vumat (in place)", status, message);
        }
        if (memcmp(stress_alias, stress_new, sizeof stress_alias) != 0 ||
            memcmp(state_alias, state_new, sizeof state_alias) != 0 ||
            memcmp(energy_alias, energy_new, sizeof energy_alias) != 0) {
            fail("in-place (aliased) VUMAT arrays differ from separate ones", STOSS_STATUS_OK,
                 "");
        }
        time += dt;
        for (int i = 0; i < NBLOCK; ++i) {
            total[i] += increment[i];
            const double energy = state_new[i + NBLOCK * STOSS_HISTORY_INTERNAL_ENERGY];
            /* enerInternNew is the energy per unit mass: E / rho0, bit for bit. */
            if (energy_new[i] != energy / block->density) {
                fail("enerInternNew != E / rho0", STOSS_STATUS_OK, "");
            }
            if (state_new[i + NBLOCK * 8] != 42.0 + i || state_new[i + NBLOCK * 9] != -7.0) {
                fail("host state variables were not carried over", STOSS_STATUS_OK, "");
            }
            double s[6];
            for (int k = 0; k < 6; ++k) {
                s[k] = stress_new[i + NBLOCK * k];
            }
            const double values[20] = {
                time, total[i], 0.0, 0.0, 0.0, 0.0, 0.0, s[0], s[1], s[2], s[3], s[4], s[5],
                state_new[i + NBLOCK * STOSS_HISTORY_PLASTIC_STRAIN],
                state_new[i + NBLOCK * STOSS_HISTORY_PLASTIC_STRAIN_RATE],
                state_new[i + NBLOCK * STOSS_HISTORY_TEMPERATURE],
                state_new[i + NBLOCK * STOSS_HISTORY_DAMAGE], energy, wave_speed[i],
                state_new[i + NBLOCK * STOSS_HISTORY_FLAGS]};
            write_record(files[i], values);
        }
        /* Abaqus swaps old and new between increments. */
        memcpy(stress_old, stress_new, sizeof stress_old);
        memcpy(state_old, state_new, sizeof state_old);
        memcpy(energy_old, energy_new, sizeof energy_old);
    }
    for (int i = 0; i < NBLOCK; ++i) {
        fclose(files[i]);
    }
}

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s <output directory>\n", argv[0]);
        return 2;
    }
    output_directory = argv[1];
    char message[MESSAGE_CAPACITY];

    if (stoss_layout_version() != STOSS_LAYOUT_VERSION ||
        stoss_material_block_size() != sizeof(StossMaterialBlock)) {
        fail("header and library disagree on the block layout", STOSS_STATUS_OK, "");
    }

    /* 4340 steel (the library's defaults) with Johnson-Cook failure switched on. */
    StossMaterialBlock jc;
    StossStatus status = stoss_material_defaults_4340(&jc);
    if (status != STOSS_STATUS_OK) {
        fail("stoss_material_defaults_4340", status, "");
    }
    jc.failure.johnson_cook_enabled = 1;
    status = stoss_material_validate(&jc, message, sizeof message);
    if (status != STOSS_STATUS_OK) {
        fail("validate jc", status, message);
    }
    const double jc_paths[2] = {0.3, -0.3};
    const char *const jc_names[2] = {"batch_jc_tension", "batch_jc_compression"};
    batch_case(&jc, 2, jc_paths, 300, 1.0e4, jc_names);

    /* 4340 with a Mie-Gruneisen EoS (illustrative test constants) and the lagged rate. */
    StossMaterialBlock mg;
    stoss_material_defaults_4340(&mg);
    mg.eos_model = STOSS_EOS_MODEL_MIE_GRUNEISEN;
    mg.eos.mie_gruneisen.reference_density = 7830.0;
    mg.eos.mie_gruneisen.sound_speed = 4570.0;
    mg.eos.mie_gruneisen.s1 = 1.49;
    mg.eos.mie_gruneisen.s2 = 0.0;
    mg.eos.mie_gruneisen.s3 = 0.0;
    mg.eos.mie_gruneisen.gamma0 = 1.93;
    mg.eos.mie_gruneisen.volume_correction = 0.5;
    mg.rate_treatment = STOSS_RATE_TREATMENT_LAGGED;
    const double mg_path[1] = {-0.2};
    const char *const mg_names[1] = {"batch_mg_lagged"};
    batch_case(&mg, 1, mg_path, 400, 1.0e5, mg_names);

    /* Zerilli-Armstrong BCC (Armco-iron constants, 65 MPa athermal stress), 4340 elasticity. */
    StossMaterialBlock za;
    stoss_material_defaults_4340(&za);
    za.strength_model = STOSS_STRENGTH_MODEL_ZERILLI_ARMSTRONG_BCC;
    za.strength.zerilli_armstrong.athermal_stress = 65.0e6;
    za.strength.zerilli_armstrong.c1 = 1033.0e6;
    za.strength.zerilli_armstrong.c2 = 0.0;
    za.strength.zerilli_armstrong.c3 = 0.00698;
    za.strength.zerilli_armstrong.c4 = 0.000415;
    za.strength.zerilli_armstrong.c5 = 266.0e6;
    za.strength.zerilli_armstrong.exponent = 0.289;
    za.strength.zerilli_armstrong.reference_rate = 1.0;
    vumat_case(&za);

    /* JC 4340 as composed terms with the diagnosis' high-rate upturn (layout 2). */
    StossMaterialBlock upturn;
    stoss_material_defaults_4340(&upturn);
    upturn.strength_model = STOSS_STRENGTH_MODEL_COMPOSED;
    StossComposed *c = &upturn.strength.composed;
    c->hardening_model = STOSS_HARDENING_MODEL_POWER;
    c->rate_model = STOSS_RATE_MODEL_LOG_UPTURN;
    c->thermal_model = STOSS_THERMAL_MODEL_HOMOLOGOUS_POWER;
    c->hardening.yield_stress = 792.0e6;
    c->hardening.hardening_modulus = 510.0e6;
    c->hardening.exponent = 0.26;
    c->rate.rate_sensitivity = 0.014;
    c->rate.reference_rate = 1.0;
    c->rate.upturn_exponent = 0.08;
    c->rate.upturn_rate = 2.0e3;
    c->thermal.exponent = 1.03;
    c->thermal.reference_temperature = 298.0;
    c->thermal.melting_temperature = 1793.0;
    status = stoss_material_validate(&upturn, message, sizeof message);
    if (status != STOSS_STATUS_OK) {
        fail("validate upturn", status, message);
    }
    const double upturn_path[1] = {0.3};
    const char *const upturn_names[1] = {"batch_jc_upturn_tension"};
    batch_case(&upturn, 1, upturn_path, 300, 1.0e4, upturn_names);

    /* RHT concrete (layout 3): seed 001's 92 MPa HPC over P-alpha, the library's defaults;
       one point crushed in uniaxial strain, one pulled until the hydro tensile limit fails it. */
    StossMaterialBlock rht;
    status = stoss_material_defaults_hpc92(&rht);
    if (status != STOSS_STATUS_OK) {
        fail("stoss_material_defaults_hpc92", status, "");
    }
    status = stoss_material_validate(&rht, message, sizeof message);
    if (status != STOSS_STATUS_OK) {
        fail("validate rht", status, message);
    }
    const double rht_compression[1] = {-0.05};
    const char *const rht_compression_names[1] = {"batch_rht_compression"};
    batch_case(&rht, 1, rht_compression, 250, 1.0e3, rht_compression_names);
    const double rht_tension[1] = {0.002};
    const char *const rht_tension_names[1] = {"batch_rht_tension"};
    batch_case(&rht, 1, rht_tension, 200, 1.0e3, rht_tension_names);

    /* K&C concrete (layout 5): seed 001's 100 MPa HPC over the tabulated EoS of table 5.2,
       the library's defaults; one point crushed in uniaxial strain, one pulled past the
       tensile peak into softening. */
    StossMaterialBlock kc;
    status = stoss_material_defaults_kc100(&kc);
    if (status != STOSS_STATUS_OK) {
        fail("stoss_material_defaults_kc100", status, "");
    }
    status = stoss_material_validate(&kc, message, sizeof message);
    if (status != STOSS_STATUS_OK) {
        fail("validate kc", status, message);
    }
    const double kc_compression[1] = {-0.03};
    const char *const kc_compression_names[1] = {"batch_kc_compression"};
    batch_case(&kc, 1, kc_compression, 250, 1.0e2, kc_compression_names);
    const double kc_tension[1] = {0.0005};
    const char *const kc_tension_names[1] = {"batch_kc_tension"};
    batch_case(&kc, 1, kc_tension, 250, 1.0e2, kc_tension_names);

    printf("uniaxial_strain: wrote 10 histories to %s\n", output_directory);
    return 0;
}
