/* Shared term plumbing: allocation and destruction of eo_term (see term.h). */
#include "term.h"

int eo_term_alloc(eo_sys *s, const eo_term_ops *ops, int with_vec, eo_term **out)
{
    *out = NULL;
    eo_term *t = eo_calloc(s->ctx, 1, sizeof *t);
    if (!t) return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (term %s)", ops->name);
    t->ops = ops;
    t->weight = 1.0;
    if (with_vec) {
        t->vec = eo_calloc(s->ctx, (size_t)s->n_full, sizeof(double));
        if (!t->vec) {
            eo_free(s->ctx, t);
            return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (term %s)", ops->name);
        }
    }
    *out = t;
    return EO_OK;
}

void eo_term_destroy(eo_ctx *ctx, eo_term **t)
{
    if (!t || !*t) return;
    if ((*t)->ops->destroy) (*t)->ops->destroy(*t, ctx);
    eo_free(ctx, (*t)->vec);
    eo_free(ctx, *t);
    *t = NULL;
}

int eo_term_attach_vertex_blocks(eo_sys *s, int *dofs, int *group)
{
    for (int j = 0; j < s->n_full; j++) dofs[j] = s->full2free[j];
    int h = eo_assembler_add_elements(s->ctx, s->as, s->nv, 3, dofs);
    if (h < 0) return h;
    *group = h;
    return EO_OK;
}
