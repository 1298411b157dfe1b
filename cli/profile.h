/* `--profile` of elastopt run and bench: where the solver's time went, per step and in
 * total (cli/profile.c), read from the library's eo_solver_get_profile (solver.h). */
#ifndef ELASTOPT_CLI_PROFILE_H
#define ELASTOPT_CLI_PROFILE_H

#include <stdio.h>

#include "elastopt/sim.h"
#include "elastopt/impl/method.h"

typedef struct eo_cli_profile {
    int on;           /* 0: every call is a no-op */
    FILE *out;        /* stdout */
    eo_profile last;  /* the solver's profile after the previous step */
} eo_cli_profile;

/* Start: on = enabled; remembers the sim's solver profile and prints the BLAS line. */
void eo_cli_profile_begin(eo_cli_profile *p, int on, const eo_sim *sim);
/* After step `step` (1-based): one line with what this step added. */
void eo_cli_profile_step(eo_cli_profile *p, const eo_sim *sim, int step);
/* At the end: the table of the totals since begin (title: e.g. the scene name). */
void eo_cli_profile_total(eo_cli_profile *p, const eo_sim *sim, const char *title);
/* The table of one profile (also used by `bench --profile` per configuration). */
void eo_cli_profile_print(FILE *out, const char *title, const eo_profile *pr);

/* "profile: BLAS OpenBLAS 0.3.21, core SkylakeX (fixed from Prescott), 2 threads (...)" */
void eo_cli_profile_blas(FILE *out);

#endif
