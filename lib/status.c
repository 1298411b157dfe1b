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
static char reason_names[32][EO_REASON_NAME_MAX];
static int reason_values[32];
static int reason_count = -1;

static void reason_names_init(void)
{
    static const char *const names[] = {
#define X(name, value, str) #name,
        EO_REASON_LIST(X)
#undef X
    };
    static const int values[] = {
#define X(name, value, str) value,
        EO_REASON_LIST(X)
#undef X
    };
    int n = (int)(sizeof values / sizeof values[0]);
    for (int k = 0; k < n && k < 32; k++) {
        const char *s = names[k] + 3; /* skip "EO_" */
        if (s[0] == 'R' && s[1] == 'E' && s[2] == 'A' && s[3] == 'S' && s[6] == '_')
            s += 7; /* "REASON_ITERATING" -> "ITERATING" */
        int j = 0;
        for (; s[j] && j < EO_REASON_NAME_MAX - 1; j++)
            reason_names[k][j] = (char)((s[j] >= 'A' && s[j] <= 'Z') ? s[j] - 'A' + 'a' : s[j]);
        reason_names[k][j] = 0;
        reason_values[k] = values[k];
    }
    reason_count = n;
}

const char *eo_reason_name(int reason)
{
    if (reason_count < 0) reason_names_init();
    for (int k = 0; k < reason_count; k++)
        if (reason_values[k] == reason) return reason_names[k];
    return "unknown";
}
