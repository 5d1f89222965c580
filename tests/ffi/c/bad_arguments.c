/*
 * Bad-argument test of the stoss C ABI: NULL pointers, n = 0, a wrong layout version or
 * struct size, invalid constants, NaN strain, negative and zero dt, inverted volumes,
 * non-finite state, overflow, too-small buffers, bad dimensions, misaligned arrays. Each call
 * must return its documented status code (docs/user-material.md), leave the state of a
 * failing point untouched, and never crash (the script also runs this under valgrind).
 *
 * Prints one "ok"/"not ok" line per check (TAP style); exit status = number of failures.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "stoss_kernel.h"

static int failures = 0;
static int checks = 0;

static void check(int condition, const char *description) {
    ++checks;
    printf("%s %d - %s\n", condition ? "ok" : "not ok", checks, description);
    if (!condition) {
        ++failures;
    }
}

static void check_status(StossStatus got, StossStatus expected, const char *description) {
    char line[512];
    snprintf(line, sizeof line, "%s: %s (expected %s)", description, stoss_status_name(got),
             stoss_status_name(expected));
    check(got == expected, line);
}

static int starts_with(const char *text, const char *prefix) {
    return strncmp(text, prefix, strlen(prefix)) == 0;
}

enum { N = 3 };

typedef struct Points {
    double strain[6][N];
    double volume[N];
    double stress[6][N];
    double plastic_strain[N], plastic_strain_rate[N], temperature[N], damage[N];
    double relative_volume[N], internal_energy[N], eos_history[N];
    uint32_t flags[N];
    double wave_speed[N];
    int32_t failed[N], status[N];
} Points;

static StossBatchInput input_of(Points *p, int with_volume) {
    StossBatchInput input;
    for (int k = 0; k < 6; ++k) {
        input.strain_increment[k] = p->strain[k];
    }
    input.relative_volume = with_volume ? p->volume : NULL;
    return input;
}

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

/* Fresh points: initial state, compressive increment on every point. */
static void reset(Points *p, const StossMaterialBlock *block) {
    memset(p, 0, sizeof *p);
    StossBatchState state = state_of(p);
    stoss_state_init(block, N, &state, NULL, 0);
    for (int i = 0; i < N; ++i) {
        p->strain[0][i] = -1e-3;
        p->volume[i] = 1.0;
        p->status[i] = -1;
    }
}

static StossStatus update(const StossMaterialBlock *block, Points *p, size_t n, double dt,
                          int with_volume, size_t *first_failure, char *message,
                          size_t capacity) {
    StossBatchInput input = input_of(p, with_volume);
    StossBatchState state = state_of(p);
    StossBatchOutput output = {p->wave_speed, p->failed, p->status, NULL};
    return stoss_update_batch(block, n, dt, &input, &state, &output, first_failure, message,
                              capacity);
}

int main(void) {
    char message[256];
    size_t first_failure = 12345;
    StossMaterialBlock block;
    Points p;

    /* --- the material block ------------------------------------------------------------- */
    check_status(stoss_material_defaults_4340(NULL), STOSS_STATUS_NULL_POINTER,
                 "defaults into NULL");
    check_status(stoss_material_defaults_4340(&block), STOSS_STATUS_OK, "defaults");
    check_status(stoss_material_validate(&block, message, sizeof message), STOSS_STATUS_OK,
                 "defaults validate");
    check(message[0] == '\0', "success clears the message");
    check_status(stoss_material_validate(NULL, message, sizeof message),
                 STOSS_STATUS_NULL_POINTER, "validate NULL block");
    check(starts_with(message, "block:"), "NULL block message names the argument");
    check_status(stoss_material_validate(NULL, NULL, 0), STOSS_STATUS_NULL_POINTER,
                 "NULL message buffer is allowed");

    StossMaterialBlock bad = block;
    bad.layout_version = STOSS_LAYOUT_VERSION + 1;
    check_status(stoss_material_validate(&bad, message, sizeof message),
                 STOSS_STATUS_BAD_LAYOUT_VERSION, "wrong layout version");
    check(starts_with(message, "layout_version:"), "layout message names the field");
    bad = block;
    bad.struct_size = (uint32_t)sizeof(StossMaterialBlock) - 8;
    check_status(stoss_material_validate(&bad, message, sizeof message),
                 STOSS_STATUS_BAD_STRUCT_SIZE, "wrong struct size");
    bad = block;
    bad.strength.johnson_cook.yield_stress = -1.0;
    check_status(stoss_material_validate(&bad, message, sizeof message),
                 STOSS_STATUS_INVALID_PARAMETER, "negative yield stress");
    check(strcmp(message, "strength.johnson_cook: yield_stress: must be > 0, got -1") == 0,
          "invalid parameter message names section and field");
    bad = block;
    bad.eos_model = 99;
    check_status(stoss_material_validate(&bad, message, sizeof message),
                 STOSS_STATUS_INVALID_PARAMETER, "unknown EoS code");
    bad = block;
    bad.density = NAN;
    check_status(stoss_material_validate(&bad, message, sizeof message),
                 STOSS_STATUS_INVALID_PARAMETER, "NaN density");

    /* A short buffer truncates the message and still terminates it. */
    char small[8];
    memset(small, 'x', sizeof small);
    stoss_material_validate(&bad, small, sizeof small);
    check(small[7] == '\0' && strlen(small) == 7, "message truncated to capacity - 1");
    char untouched[4] = {'a', 'b', 'c', 'd'};
    stoss_material_validate(&bad, untouched, 0);
    check(untouched[0] == 'a', "capacity 0 writes nothing");

    /* --- the batch ---------------------------------------------------------------------- */
    reset(&p, &block);
    StossBatchInput input = input_of(&p, 0);
    StossBatchState state = state_of(&p);
    check_status(stoss_update_batch(&block, N, 1e-6, NULL, &state, NULL, NULL, message,
                                    sizeof message),
                 STOSS_STATUS_NULL_POINTER, "NULL input struct");
    check_status(stoss_update_batch(&block, N, 1e-6, &input, NULL, NULL, NULL, message,
                                    sizeof message),
                 STOSS_STATUS_NULL_POINTER, "NULL state struct");
    check_status(stoss_update_batch(NULL, N, 1e-6, &input, &state, NULL, NULL, message,
                                    sizeof message),
                 STOSS_STATUS_NULL_POINTER, "NULL block in update");
    state.damage = NULL;
    check_status(stoss_update_batch(&block, N, 1e-6, &input, &state, NULL, NULL, message,
                                    sizeof message),
                 STOSS_STATUS_NULL_POINTER, "NULL array inside the state");
    check(starts_with(message, "state.damage:"), "NULL array message names the field");
    input.strain_increment[3] = NULL;
    state = state_of(&p);
    check_status(stoss_update_batch(&block, N, 1e-6, &input, &state, NULL, NULL, message,
                                    sizeof message),
                 STOSS_STATUS_NULL_POINTER, "NULL strain component");
    check(starts_with(message, "input.strain_increment[3] (xy):"),
          "NULL component message names the component");

    input = input_of(&p, 0);
    check_status(stoss_update_batch(&block, 0, 1e-6, &input, &state, NULL, NULL, message,
                                    sizeof message),
                 STOSS_STATUS_ZERO_POINTS, "n = 0");
    check_status(stoss_state_init(&block, 0, &state, message, sizeof message),
                 STOSS_STATUS_ZERO_POINTS, "state_init n = 0");
    bad = block;
    bad.layout_version = 0;
    check_status(stoss_update_batch(&bad, N, 1e-6, &input, &state, NULL, NULL, message,
                                    sizeof message),
                 STOSS_STATUS_BAD_LAYOUT_VERSION, "update with a wrong layout version");

    /* NaN strain on point 1: only point 1 fails; its state is untouched. */
    reset(&p, &block);
    p.strain[1][1] = NAN;
    Points before = p;
    StossStatus status = update(&block, &p, N, 1e-7, 0, &first_failure, message, sizeof message);
    check_status(status, STOSS_STATUS_NON_FINITE_INPUT, "NaN strain");
    check(first_failure == 1, "first_failure is the NaN point");
    check(starts_with(message, "point 1:"), "message names the point");
    check(p.status[0] == STOSS_STATUS_OK && p.status[1] == STOSS_STATUS_NON_FINITE_INPUT &&
              p.status[2] == STOSS_STATUS_OK,
          "per-point statuses");
    int unchanged = 1;
    for (int k = 0; k < 6; ++k) {
        unchanged &= p.stress[k][1] == before.stress[k][1];
    }
    unchanged &= p.relative_volume[1] == before.relative_volume[1] &&
                 p.temperature[1] == before.temperature[1] && p.flags[1] == before.flags[1] &&
                 p.internal_energy[1] == before.internal_energy[1];
    check(unchanged, "failing point keeps its state");
    check(p.stress[0][0] < 0.0 && p.stress[0][2] == p.stress[0][0] &&
              p.relative_volume[0] < 1.0,
          "the other points proceed");

    reset(&p, &block);
    check_status(update(&block, &p, N, -1e-6, 0, &first_failure, message, sizeof message),
                 STOSS_STATUS_NON_POSITIVE_TIME_STEP, "negative dt");
    check(first_failure == 0 && p.status[2] == STOSS_STATUS_NON_POSITIVE_TIME_STEP,
          "negative dt fails every point");
    check(p.relative_volume[0] == 1.0 && p.stress[0][0] == 0.0, "negative dt changes nothing");
    check_status(update(&block, &p, N, 0.0, 0, &first_failure, message, sizeof message),
                 STOSS_STATUS_NON_POSITIVE_TIME_STEP, "zero dt");
    check_status(update(&block, &p, N, NAN, 0, &first_failure, message, sizeof message),
                 STOSS_STATUS_NON_FINITE_INPUT, "NaN dt");

    reset(&p, &block);
    p.volume[2] = -0.5;
    check_status(update(&block, &p, N, 1e-7, 1, &first_failure, message, sizeof message),
                 STOSS_STATUS_NON_POSITIVE_VOLUME, "negative relative volume");
    check(first_failure == 2, "first_failure is the inverted point");

    reset(&p, &block);
    p.temperature[0] = INFINITY;
    check_status(update(&block, &p, N, 1e-7, 0, &first_failure, message, sizeof message),
                 STOSS_STATUS_NON_FINITE_STATE, "infinite temperature in the state");

    /* Finite but impossible states, as a host integrator might pass them. */
    reset(&p, &block);
    p.temperature[1] = -5.0;
    check_status(update(&block, &p, N, 1e-7, 0, &first_failure, message, sizeof message),
                 STOSS_STATUS_INADMISSIBLE_STATE, "temperature -5 K in the state");
    check(first_failure == 1 && p.status[1] == STOSS_STATUS_INADMISSIBLE_STATE &&
              p.status[0] == STOSS_STATUS_OK,
          "only the point with the impossible state fails");
    check(starts_with(message, "point 1: incoming state.temperature = -5"),
          "the message names the point, the variable and its value");
    check(p.temperature[1] == -5.0, "the failing point keeps its state");
    reset(&p, &block);
    p.damage[2] = 2.0;
    check_status(update(&block, &p, N, 1e-7, 0, &first_failure, message, sizeof message),
                 STOSS_STATUS_INADMISSIBLE_STATE, "damage 2 in the state");
    check(starts_with(message, "point 2: incoming state.damage = 2"), "damage message");
    reset(&p, &block);
    p.plastic_strain[0] = -1.0;
    check_status(update(&block, &p, N, 1e-7, 0, &first_failure, message, sizeof message),
                 STOSS_STATUS_INADMISSIBLE_STATE, "plastic strain -1 in the state");
    check(starts_with(message, "point 0: incoming state.plastic_strain = -1"),
          "plastic strain message");

    /* Mie-Gruneisen beyond its limiting compression (S1 = 2: V = 1/2) overflows. */
    StossMaterialBlock mg = block;
    mg.eos_model = STOSS_EOS_MODEL_MIE_GRUNEISEN;
    mg.eos.mie_gruneisen.reference_density = 7830.0;
    mg.eos.mie_gruneisen.sound_speed = 4500.0;
    mg.eos.mie_gruneisen.s1 = 2.0;
    mg.eos.mie_gruneisen.gamma0 = 2.0;
    reset(&p, &mg);
    p.volume[0] = 0.5;
    check_status(update(&mg, &p, 1, 1e-7, 1, &first_failure, message, sizeof message),
                 STOSS_STATUS_NON_FINITE_RESULT, "EoS overflow");
    check(p.relative_volume[0] == 1.0, "overflowing point keeps its state");

    /* Misaligned array. */
    reset(&p, &block);
    input = input_of(&p, 0);
    state = state_of(&p);
    double storage[N + 1];
    memset(storage, 0, sizeof storage);
    input.strain_increment[0] = (const double *)(const void *)((const char *)storage + 1);
    check_status(stoss_update_batch(&block, N, 1e-6, &input, &state, NULL, NULL, message,
                                    sizeof message),
                 STOSS_STATUS_MISALIGNED_POINTER, "misaligned strain array");

    /* --- cards and adapters ------------------------------------------------------------- */
    double card[STOSS_CARD_MAX_LENGTH];
    size_t length = 0;
    check_status(stoss_material_to_card(&block, card, 5, &length, message, sizeof message),
                 STOSS_STATUS_BUFFER_TOO_SMALL, "card capacity too small");
    check(length == STOSS_CARD_FIXED_LENGTH, "needed card length reported");
    check_status(stoss_material_to_card(&block, card, STOSS_CARD_MAX_LENGTH, &length, message,
                                        sizeof message),
                 STOSS_STATUS_OK, "card");
    check(card[STOSS_CARD_BULK_MODULUS - 1] == 159.0e9 &&
              card[STOSS_CARD_SHEAR_MODULUS - 1] == 81.8e9,
          "bulk and shear moduli at the documented card positions");
    StossMaterialBlock parsed;
    check_status(stoss_material_from_card(card, 20, &parsed, message, sizeof message),
                 STOSS_STATUS_INVALID_PARAMETER, "card too short");
    double wrong[STOSS_CARD_MAX_LENGTH];
    memcpy(wrong, card, sizeof wrong);
    wrong[0] = (double)(STOSS_LAYOUT_VERSION + 1);
    check_status(stoss_material_from_card(wrong, length, &parsed, message, sizeof message),
                 STOSS_STATUS_BAD_LAYOUT_VERSION, "card with a wrong version");
    wrong[0] = 1.0;
    wrong[6] = 2.5;
    check_status(stoss_material_from_card(wrong, length, &parsed, message, sizeof message),
                 STOSS_STATUS_INVALID_PARAMETER, "non-integer model code on the card");
    check(starts_with(message, "card P7"), "card message names the slot");
    check_status(stoss_material_from_card(NULL, length, &parsed, message, sizeof message),
                 STOSS_STATUS_NULL_POINTER, "NULL card");

    double eps[6] = {-1e-3, 0, 0, 0, 0, 0}, sig[6] = {0}, hsv[8] = {0};
    check_status(stoss_lsdyna_umat(card, length, 1, 1e-6, eps, sig, hsv, 4, NULL, NULL, NULL,
                                   NULL, message, sizeof message),
                 STOSS_STATUS_BUFFER_TOO_SMALL, "umat with nhv = 4");
    check_status(stoss_lsdyna_umat(card, length, 0, 1e-6, eps, sig, hsv, 8, NULL, NULL, NULL,
                                   NULL, message, sizeof message),
                 STOSS_STATUS_ZERO_POINTS, "umat with nlq = 0");
    check_status(stoss_lsdyna_umat(card, length, 1, -1e-6, eps, sig, hsv, 8, NULL, NULL, NULL,
                                   &first_failure, message, sizeof message),
                 STOSS_STATUS_NON_POSITIVE_TIME_STEP, "umat with negative dt");
    check(hsv[STOSS_HISTORY_RELATIVE_VOLUME] == 0.0 && sig[0] == 0.0,
          "umat failure leaves sig and hsv untouched");
    check_status(stoss_lsdyna_umat(card, length, 1, 1e-6, eps, sig, NULL, 8, NULL, NULL, NULL,
                                   NULL, message, sizeof message),
                 STOSS_STATUS_NULL_POINTER, "umat with NULL hsv");

    double old_state[8] = {0}, new_state[8], energy_old[1] = {0}, energy_new[1];
    double stress_new[6];
    check_status(stoss_abaqus_vumat(card, length, 1, 2, 1, 8, 1e-6, 1e-6, 1e-6, eps, sig,
                                    old_state, energy_old, stress_new, new_state, energy_new,
                                    NULL, NULL, NULL, message, sizeof message),
                 STOSS_STATUS_INVALID_ARGUMENT, "vumat plane stress (ndir = 2)");
    check_status(stoss_abaqus_vumat(card, length, 1, 3, 3, 6, 1e-6, 1e-6, 1e-6, eps, sig,
                                    old_state, energy_old, stress_new, new_state, energy_new,
                                    NULL, NULL, NULL, message, sizeof message),
                 STOSS_STATUS_BUFFER_TOO_SMALL, "vumat with nstatev = 6");
    eps[0] = NAN;
    int32_t point_status[1] = {-1};
    check_status(stoss_abaqus_vumat(card, length, 1, 3, 3, 8, 1e-6, 1e-6, 1e-6, eps, sig,
                                    old_state, energy_old, stress_new, new_state, energy_new,
                                    NULL, point_status, &first_failure, message,
                                    sizeof message),
                 STOSS_STATUS_NON_FINITE_INPUT, "vumat with NaN strain");
    check(point_status[0] == STOSS_STATUS_NON_FINITE_INPUT && stress_new[0] == sig[0] &&
              new_state[STOSS_HISTORY_RELATIVE_VOLUME] == 0.0,
          "vumat failing point: new = old");

    /* --- status names ------------------------------------------------------------------- */
    check(strcmp(stoss_status_name(STOSS_STATUS_PANIC), "STOSS_STATUS_PANIC") == 0,
          "status name");
    check(strcmp(stoss_status_name(-3), "STOSS_STATUS_UNKNOWN") == 0, "unknown status name");

    printf("# %d checks, %d failed\n", checks, failures);
    return failures;
}
