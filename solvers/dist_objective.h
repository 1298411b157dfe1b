/* The distributed view of a part's objective (solvers/dist_objective.c), internal to
 * solvers/. */
#ifndef EO_DIST_OBJECTIVE_H
#define EO_DIST_OBJECTIVE_H

#include "elastopt/objective.h"

typedef struct eo_dist_view {
    eo_objective obj;          /* the view the optimizer minimizes (obj.space = space) */
    eo_objective_ops ops;      /* its ops: the part's optional ones it can give */
    eo_objective *local;       /* this part's objective (its terms only) */
    const eo_vspace *space;    /* from the context's hook, borrowed */
    eo_ctx *ctx;
} eo_dist_view;

/* Set *v up as the distributed view of `local` (a part of a distributed problem: the
 * context has eo_dist_hooks with a `space` hook; collective). EO_ERR_UNSUPPORTED with a
 * message when the context cannot give a vector space. */
int eo_dist_view_init(eo_dist_view *v, eo_ctx *ctx, eo_objective *local);
/* x (n) made equal to its owner's value at every copy (collective). */
int eo_dist_view_consistent(const eo_vspace *s, double *x);

#endif
