/* Which command-line words are PETSc options (-ksp_type, -pc_type, -log_view, ...): the
 * CLI passes them to PETSc instead of parsing them. Shared by the module (which takes
 * them out of argv) and the CLI (which loads the module when it sees one). */
#ifndef EO_PETSC_OPTIONS_H
#define EO_PETSC_OPTIONS_H

#include <string.h>

static inline int eo_petsc_option_word(const char *a)
{
    static const char *const pre[] = {"-ksp_", "-pc_", "-mat_", "-snes_", "-tao_", "-log_", "-info", "-options_",
                                      "-malloc", "-on_error", "-sub_", "-mg_", "-memory_view", "-petscpartitioner_", NULL};
    for (int i = 0; pre[i]; i++)
        if (strncmp(a, pre[i], strlen(pre[i])) == 0) return 1;
    return 0;
}

/* The Hessian fixes and line searches petsc_newton runs distributed (NULL) or the message
 * why not. Shared by the module (at the first minimization) and the CLI (at load, before
 * anything is written). */
static inline const char *eo_petsc_newton_refuses(const char *hessfix, const char *linesearch)
{
    static const char *const hf[] = {"none", "shift", "clamp", "abs", "project_on_demand", NULL};
    static const char *const ls[] = {"auto", "backtracking", "nonmonotone", "none", NULL};
    int ok = 0;
    for (int i = 0; hf[i]; i++) ok |= strcmp(hessfix, hf[i]) == 0;
    if (!ok) return "Hessian fix has no distributed form; use none, shift, clamp, abs or project_on_demand";
    ok = 0;
    for (int i = 0; ls[i]; i++) ok |= strcmp(linesearch, ls[i]) == 0;
    if (!ok) return "line search needs gradient products inside the search; use backtracking, nonmonotone or none";
    return NULL;
}

#endif
