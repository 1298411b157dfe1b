/* Which command-line words are PETSc options (-ksp_type, -pc_type, -log_view, ...): the
 * CLI passes them to PETSc instead of parsing them. Shared by the module (which takes
 * them out of argv) and the CLI (which loads the module when it sees one). */
#ifndef EO_PETSC_OPTIONS_H
#define EO_PETSC_OPTIONS_H

#include <string.h>

static inline int eo_petsc_option_word(const char *a)
{
    static const char *const pre[] = {"-ksp_", "-pc_", "-mat_", "-snes_", "-tao_", "-log_", "-info", "-options_",
                                      "-malloc", "-on_error", "-sub_", "-mg_", "-memory_view", "-petscpartitioner_",
                                      "-matptap_", NULL};
    for (int i = 0; pre[i]; i++)
        if (strncmp(a, pre[i], strlen(pre[i])) == 0) return 1;
    return 0;
}

#endif
