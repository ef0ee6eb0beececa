/* One footprint for every change (core/map/footprint.h, edit.h).
 *
 * Core: for every scheme, with and without details, the footprint
 * st_hier_edit reports is the set its query st_hier_edit_footprint gives
 * before the edit, every value the edit
 * changed is in it, and st_hier_restore of the saved values gives the
 * hierarchy back bit for bit, reporting the same set.
 *
 * Document and renderer (headless OSMesa): after a vertex drag, a brush dab
 * and an undo, the vertices the renderer re-reads (st_rgeom.reread) are
 * exactly the drawn vertices of the footprint core reported, and the
 * buffers, on the CPU and on the GPU, equal a fresh build; also with the
 * interest box on (the surface from the display's footprint, the cage from
 * the model's). */
#include "testlib.h"

#include <stdlib.h>
#include <string.h>

#include "core/multires/edit.h"
#include "editor.h"
#include "render/headless.h"
#include "render/renderer.h"

/* ---- key sets ------------------------------------------------------------------ */

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* Sorted distinct keys of f (caller frees). */
static uint64_t *key_set(const st_footprint *f, uint32_t *n)
{
    uint64_t *k = malloc((size_t)(f->n ? f->n : 1) * sizeof *k);
    if (f->n) memcpy(k, f->keys, (size_t)f->n * sizeof *k);
    qsort(k, f->n, sizeof *k, cmp_u64);
    uint32_t m = 0;
    for (uint32_t i = 0; i < f->n; i++)
        if (!m || k[m - 1] != k[i]) k[m++] = k[i];
    *n = m;
    return k;
}

static int same_sets(const st_footprint *a, const st_footprint *b)
{
    uint32_t na, nb;
    uint64_t *ka = key_set(a, &na), *kb = key_set(b, &nb);
    int eq = na == nb && !memcmp(ka, kb, (size_t)na * sizeof *ka);
    free(ka);
    free(kb);
    return eq;
}

static int has_key(const uint64_t *set, uint32_t n, uint64_t key)
{
    return bsearch(&key, set, n, sizeof *set, cmp_u64) != NULL;
}

/* ---- core ------------------------------------------------------------------------ */

/* Every position and detail of every live vertex at every level, keyed. */
typedef struct values { uint64_t *key; double (*v)[3]; uint32_t n; } values;

static void values_take(const st_hier *h, values *out)
{
    uint32_t cap = 1024;
    out->n = 0;
    out->key = malloc(cap * sizeof *out->key);
    out->v = malloc(cap * sizeof *out->v);
    for (unsigned l = 0; l <= h->map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it))
            for (int kind = 0; kind < 2; kind++) {
                if (out->n == cap) {
                    cap *= 2;
                    out->key = realloc(out->key, cap * sizeof *out->key);
                    out->v = realloc(out->v, cap * sizeof *out->v);
                }
                out->key[out->n] = st_fp_key(l, kind, v);
                st_hier_value(h, out->key[out->n], out->v[out->n]);
                out->n++;
            }
    }
}

static void values_free(values *v) { free(v->key); free(v->v); memset(v, 0, sizeof *v); }

static void mesh_torus(st_mesh *m) { tl_mesh_torus(m, 8, 6); }

/* details: random details on every level; without, the schemes' own local
 * predictions (st_scheme.predict_around) write the levels above. */
static void check_core(st_scheme_id id, void (*make)(st_mesh *), unsigned levels, int details)
{
    st_hier h;
    uint64_t rng = 0xf00d + id;
    tl_init_hier(&h, make, id, levels);
    if (details) tl_random_details(&h, &rng, 0.02);
    for (unsigned l = 0; l < h.map.top; l++) {
        uint32_t darts[2];
        double pos[2][3];
        darts[0] = tl_random_dart_at(&h.map, l, &rng);
        do darts[1] = tl_random_dart_at(&h.map, l, &rng);
        while (st_vert(&h.map, darts[1], l) == st_vert(&h.map, darts[0], l));
        for (int k = 0; k < 2; k++) {
            const double *p = st_dart_pos(&h.map, darts[k], l);
            for (int c = 0; c < 3; c++) pos[k][c] = p[c] + 0.07 * (c + 1) * (k ? -1 : 1);
        }
        st_footprint query = { 0 }, edit = { 0 }, back = { 0 };
        st_hier_edit_footprint(&h, l, darts, 2, &query);
        values before, after;
        values_take(&h, &before);
        /* Old values of the footprint, as undo saves them. */
        double(*old)[3] = malloc((size_t)query.n * sizeof *old);
        for (uint32_t i = 0; i < query.n; i++) st_hier_value(&h, query.keys[i], old[i]);
        st_hier_edit(&h, l, darts, (const double(*)[3])pos, 2, &edit);
        CHECKF(same_sets(&query, &edit), "%s: edit at level %u: the query's footprint (%u keys) is not the edit's (%u)",
               h.scheme->name, l, query.n, edit.n);
        /* Everything that changed is reported; what is reported lies at the
         * edit level and above. */
        values_take(&h, &after);
        uint32_t ns;
        uint64_t *set = key_set(&edit, &ns);
        uint32_t missing = 0, changed = 0, below = 0;
        for (uint32_t i = 0; i < after.n && i < before.n; i++) {
            if (after.key[i] != before.key[i] || !memcmp(after.v[i], before.v[i], sizeof after.v[i])) continue;
            changed++;
            if (!has_key(set, ns, after.key[i])) missing++;
        }
        for (uint32_t i = 0; i < ns; i++) below += st_fp_level(set[i]) < l;
        CHECKF(before.n == after.n && changed > 0 && !missing && !below,
               "%s: edit at level %u: %u values changed, %u of them not reported, %u keys below the level",
               h.scheme->name, l, changed, missing, below);
        /* Restoring the saved values gives the hierarchy back bit for bit. */
        st_hier_restore(&h, query.keys, (const double(*)[3])old, query.n, &back);
        CHECK(same_sets(&back, &query));
        values again;
        values_take(&h, &again);
        int same = again.n == before.n && !memcmp(again.key, before.key, (size_t)again.n * sizeof *again.key) &&
                   !memcmp(again.v, before.v, (size_t)again.n * sizeof *again.v);
        CHECKF(same, "%s: edit at level %u: restore is not bit-exact", h.scheme->name, l);
        free(set);
        free(old);
        values_free(&before);
        values_free(&after);
        values_free(&again);
        st_footprint_free(&query);
        st_footprint_free(&edit);
        st_footprint_free(&back);
    }
    st_hier_free(&h);
}

/* ---- document and renderer ----------------------------------------------------------- */

static int buffer_equals(const st_gl *gl, GLenum target, GLuint buf, const void *data, size_t bytes)
{
    unsigned char *b = malloc(bytes ? bytes : 1);
    gl->BindBuffer(target, buf);
    gl->GetBufferSubData(target, 0, (GLsizeiptr)bytes, b);
    gl->BindBuffer(target, 0);
    int eq = !memcmp(b, data, bytes);
    free(b);
    return eq;
}

/* The mesh g draws equals a fresh build of its level of m, on the CPU and
 * in the GPU buffers. */
static int equals_fresh(const st_gl *gl, const st_rgeom *g, const st_gpu_mesh *gm, const st_map *m)
{
    st_rgeom f;
    st_error err;
    st_rgeom_init(&f);
    if (st_rgeom_build(&f, m, g->level, &err)) return 0;
    size_t vb = (size_t)f.nverts * ST_RGEOM_VSTRIDE * sizeof(float), fb = (size_t)f.nfaces * 4 * sizeof(float);
    int eq = f.nverts == g->nverts && f.nfaces == g->nfaces && !memcmp(f.vdata, g->vdata, vb) &&
             !memcmp(f.fnormal, g->fnormal, fb) && buffer_equals(gl, GL_ARRAY_BUFFER, gm->vbo, f.vdata, vb) &&
             buffer_equals(gl, GL_TEXTURE_BUFFER, gm->tbo_face_normal, f.fnormal, fb);
    st_rgeom_free(&f);
    return eq;
}

/* The vertices g re-read in its last refresh are exactly the vertices it
 * draws whose position at its level fp reports (a key of a level <= g's). */
static int reread_is_footprint(const st_rgeom *g, const st_footprint *fp, uint32_t *count)
{
    uint32_t nv = g->nvids;
    unsigned char *want = calloc(nv ? nv : 1, 1), *got = calloc(nv ? nv : 1, 1);
    for (uint32_t i = 0; i < fp->n; i++) {
        uint64_t k = fp->keys[i];
        uint32_t v = st_fp_vid(k);
        if (st_fp_kind(k) == ST_FP_POS && st_fp_level(k) <= g->level && v < nv && g->slot[v] != ST_NIL) want[v] = 1;
    }
    for (uint32_t i = 0; i < g->nreread; i++) got[g->vid[g->reread[i]]] = 1;
    int eq = !memcmp(want, got, nv);
    *count = 0;
    for (uint32_t v = 0; v < nv; v++) *count += want[v];
    free(want);
    free(got);
    return eq;
}

/* Takes the document's change and gives it to the renderer as the window
 * does, then checks the refreshed sets and the buffers. */
static void sync_and_check(st_doc *d, st_renderer *r, const st_gl *gl, const char *what)
{
    st_doc_change ch = st_doc_take_change(d);
    const st_hier *dh = st_doc_display_hier(d);
    uint32_t ns = 0, nc = 0;
    CHECKF(ch.bits & ST_CHANGE_POSITIONS, "%s: no positions changed", what);
    CHECKF(!(ch.bits & (ST_CHANGE_ALL_POSITIONS | ST_CHANGE_TOPOLOGY)), "%s: not a local change", what);
    if (dh == &d->h) {
        CHECK(st_renderer_refresh(r, ST_TARGET_MESHES, &d->h.map, ch.footprint) == 0);
        CHECKF(reread_is_footprint(&r->surf, ch.footprint, &ns), "%s: surface re-read != core's footprint", what);
    } else {
        CHECKF(ch.bits & ST_CHANGE_DISPLAY, "%s: box on, the display did not follow", what);
        CHECK(st_renderer_refresh(r, ST_TARGET_SURFACE, &dh->map, ch.disp_footprint) == 0);
        CHECKF(reread_is_footprint(&r->surf, ch.disp_footprint, &ns), "%s: surface re-read != the display's footprint",
               what);
        CHECK(st_renderer_refresh(r, ST_TARGET_CAGE, &d->h.map, ch.footprint) == 0);
    }
    CHECKF(reread_is_footprint(&r->cage, ch.footprint, &nc), "%s: cage re-read != core's footprint", what);
    CHECKF(ns > 0 && nc > 0 && ns < r->surf.nverts, "%s: %u surface and %u cage vertices refreshed of %u", what, ns, nc,
           r->surf.nverts);
    CHECKF(equals_fresh(gl, &r->surf, &r->gsurf, &dh->map), "%s: surface buffers != a fresh build", what);
    CHECKF(equals_fresh(gl, &r->cage, &r->gcage, &d->h.map), "%s: cage buffers != a fresh build", what);
    printf("%s: %u surface vertices and %u cage vertices refreshed (of %u, %u)\n", what, ns, nc, r->surf.nverts,
           r->cage.nverts);
}

static void check_document(st_headless *hl, const char *path, const char *scheme, int box, int details)
{
    st_gl *gl = &hl->gl;
    st_error err;
    st_doc d;
    st_doc_init(&d);
    CHECKF(st_doc_open(&d, path, scheme, 3, &err) == 0, "%s", err.msg);
    uint64_t rng = 5;
    if (details) {
        tl_random_details(&d.h, &rng, 0.02);
        st_hier_synthesize(&d.h, 0);
    }
    st_doc_set_edit_level(&d, 1);
    st_doc_set_display_level(&d, 3);
    if (box) {
        st_adapt_params b = d.box;
        b.base_level = 1;
        b.max_level = 4;
        CHECKF(st_doc_set_box(&d, &b, 1, &err) == 0, "%s", err.msg);
    }
    st_renderer r;
    CHECKF(st_renderer_init(&r, gl, &err) == ST_OK, "%s", err.msg);
    st_headless_begin(hl);
    const st_hier *dh = st_doc_display_hier(&d);
    CHECK(st_renderer_set_level(&r, &dh->map, st_doc_display_map_level(&d), &err) == ST_OK);
    CHECK(st_renderer_set_cage(&r, &d.h.map, 1, &err) == ST_OK);
    (void)st_doc_take_change(&d);
    char what[128];

    /* A vertex drag (two updates, each synced). */
    uint32_t v = r.cage.vid[r.cage.nverts / 3];
    st_doc_select(&d, &v, 1, ST_SELECT_REPLACE);
    (void)st_doc_take_change(&d);
    CHECK(st_doc_drag_begin(&d) == 0);
    double d1[3] = { 0.05, 0.02, -0.03 }, d2[3] = { 0.1, -0.04, 0.02 };
    CHECK(st_doc_drag_update(&d, d1) == 0);
    snprintf(what, sizeof what, "%s%s%s: drag", scheme, box ? " (box)" : "", details ? "" : " (no details)");
    sync_and_check(&d, &r, gl, what);
    CHECK(st_doc_drag_update(&d, d2) == 0);
    sync_and_check(&d, &r, gl, what);
    st_doc_drag_end(&d);
    (void)st_doc_take_change(&d);

    /* A brush dab. */
    d.brush.tool = ST_BRUSH_DRAW;
    d.brush.radius = 0.4;
    d.brush.strength = 0.5;
    /* A dab of this radius, local: the coarse-level reach (3 edges of
     * level 1, st_doc_brush_reach) would take in the whole 18-vertex
     * level, and this checks the footprint of part of it. */
    d.brush.reach_edges = 0;
    double c[3], n[3] = { 0, 0, 1 };
    st_doc_vertex_pos(&d, r.cage.vid[r.cage.nverts / 2], c);
    CHECK(st_doc_stroke_begin(&d) == 0);
    CHECK(st_doc_stroke_dab(&d, c, n, NULL) == 0);
    snprintf(what, sizeof what, "%s%s: brush dab", scheme, box ? " (box)" : "");
    sync_and_check(&d, &r, gl, what);
    st_doc_stroke_end(&d);
    (void)st_doc_take_change(&d);

    /* Undo of the stroke, then of the drag. */
    CHECK(st_doc_undo(&d, &err) == 0);
    snprintf(what, sizeof what, "%s%s: undo of the stroke", scheme, box ? " (box)" : "");
    sync_and_check(&d, &r, gl, what);
    CHECK(st_doc_undo(&d, &err) == 0);
    snprintf(what, sizeof what, "%s%s: undo of the drag", scheme, box ? " (box)" : "");
    sync_and_check(&d, &r, gl, what);
    CHECK(gl->GetError() == GL_NO_ERROR);
    st_renderer_free(&r);
    st_doc_free(&d);
}

int main(void)
{
    static const st_scheme_id ids[] = { ST_SCHEME_CATMARK, ST_SCHEME_LOOP, ST_SCHEME_BUTTERFLY, ST_SCHEME_QUADTRI,
                                        ST_SCHEME_SQRT3, ST_SCHEME_DOOSABIN };
    for (size_t i = 0; i < sizeof ids / sizeof ids[0]; i++) {
        int tri = ids[i] == ST_SCHEME_LOOP || ids[i] == ST_SCHEME_BUTTERFLY || ids[i] == ST_SCHEME_SQRT3;
        check_core(ids[i], tri ? tl_mesh_icosa : mesh_torus, 3, 1);
        check_core(ids[i], tri ? tl_mesh_icosa : mesh_torus, 3, 0);
    }
    st_headless hl;
    st_error err;
    int rc = st_headless_init(&hl, 16, 8, 1, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    if (!rc) {
        const char *torus = STRATA_ASSETS "/torus.obj", *octa = STRATA_ASSETS "/octahedron.obj";
        check_document(&hl, torus, "catmull-clark", 0, 0);
        check_document(&hl, torus, "catmull-clark", 0, 1);
        check_document(&hl, torus, "doo-sabin", 0, 1);
        check_document(&hl, octa, "loop", 0, 1);
        check_document(&hl, torus, "catmull-clark", 1, 1);
        check_document(&hl, octa, "loop", 1, 1);
        st_headless_free(&hl);
    }
    return TEST_END();
}
