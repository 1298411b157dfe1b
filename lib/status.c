/* Status codes and convergence reasons: strings generated from the X-macro lists. */
#include "elastopt/status.h"

#include <stddef.h>

const char *eo_status_string(int status)
{
    switch (status) {
#define X(name, value, str) case value: return str;
        EO_STATUS_LIST(X)
#undef X
    }
    return "unknown status";
}

const char *eo_status_name(int status)
{
    switch (status) {
#define X(name, value, str) case value: return #name;
        EO_STATUS_LIST(X)
#undef X
    }
    return "EO_UNKNOWN";
}

const char *eo_reason_string(int reason)
{
    switch (reason) {
#define X(name, value, str) case value: return str;
        EO_REASON_LIST(X)
#undef X
    }
    return "unknown reason";
}

/* "EO_CONVERGED_DECREMENT" -> "converged_decrement", from a static table built once
 * from the same list (lower-cased copies of the names without the prefix). */
#define EO_REASON_NAME_MAX 48
#define X(name, value, str) +1
enum { N_REASONS = 0 EO_REASON_LIST(X) }; /* entries of the list: sizes the tables */
#undef X
static char reason_names[N_REASONS][EO_REASON_NAME_MAX];
static int reason_values[N_REASONS];
static int reason_count = -1;

static void reason_names_init(void)
{
    static const char *const names[N_REASONS] = {
#define X(name, value, str) #name,
        EO_REASON_LIST(X)
#undef X
    };
    static const int values[N_REASONS] = {
#define X(name, value, str) value,
        EO_REASON_LIST(X)
#undef X
    };
    for (int k = 0; k < N_REASONS; k++) {
        const char *s = names[k] + 3; /* skip "EO_" */
        if (s[0] == 'R' && s[1] == 'E' && s[2] == 'A' && s[3] == 'S' && s[6] == '_')
            s += 7; /* "REASON_ITERATING" -> "ITERATING" */
        int j = 0;
        for (; j < EO_REASON_NAME_MAX - 1 && s[j]; j++)
            reason_names[k][j] = (char)((s[j] >= 'A' && s[j] <= 'Z') ? s[j] - 'A' + 'a' : s[j]);
        reason_names[k][j] = 0;
        reason_values[k] = values[k];
    }
    reason_count = N_REASONS;
}

const char *eo_reason_name(int reason)
{
    if (reason_count < 0) reason_names_init();
    for (int k = 0; k < reason_count; k++)
        if (reason_values[k] == reason) return reason_names[k];
    return "unknown";
}
