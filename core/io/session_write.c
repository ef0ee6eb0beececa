/* Session files, the writer (session.h, docs/SESSION-FORMAT.md): the
 * chunks planned, measured and written. */
#include "core/io/session_internal.h"
#include "core/base/membudget.h"
#include "core/io/atomic_file.h"
#include "core/io/file_open.h"
#include "core/io/map_io_internal.h"
#include "core/map/pool_internal.h"
#include "core/progressive/progressive.h"
#include "core/multires/hier.h"
#include "core/fvar/fvar_internal.h"

#include <errno.h>
#include <sys/stat.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- chunk writers --------------------------------------------------------------- */

/* What the chunk writers read: the reference; for a nested HD image the
 * renumbering its hierarchy's ids are written under
 * (core/map/renumber_internal.h: the image holds live ids only); for the
 * outer file the HD image itself, made once before the counting pass, so
 * that both passes take the same bytes and the image is not made twice. */
typedef struct wsrc {
    const st_session_ref *r;
    const st_map_renumber *ids;   /* NULL: the ids as they are */
    const void *hd_img;           /* chunk hdlv's image (after hd_from), when r->hd */
    size_t hd_len;
    const unsigned char *pm;      /* chunk PMRC's payload, when the hierarchy has a recipe */
    size_t pm_len;
    unsigned char *pm_owned;      /* pm when derived for this save (freed by release) */
} wsrc;

typedef void (*chunk_fn)(st_bw *w, const wsrc *src);

static void w_hier(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    const char *name = r->h->scheme->name;
    uint32_t n = (uint32_t)strlen(name);
    st_bw_u32(w, n);
    st_bw_bytes(w, name, n);
    st_bw_u32(w, (uint32_t)r->h->opts.boundary);
    /* Bit 8: smooth triangles (0 in sessions written before the option, so
     * they load unchanged).  Bits 16-23: the progressive predictor (0, the
     * relaxation, in sessions written before the tag, which load with it;
     * core/progressive/progressive.h, point 5). */
    st_bw_u32(w, (uint32_t)r->h->opts.crease_method | (uint32_t)r->h->opts.tri_sub << 8 |
                     (uint32_t)r->h->opts.pm_predictor << 16);
    st_bw_u8(w, r->h->has_sharpness != 0);
}

static void w_map(st_bw *w, const wsrc *src)
{
    if (src->ids) st_map_write_renumbered(w, &src->r->h->map, src->ids);
    else st_map_write(w, &src->r->h->map);
}

static void w_sharp(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    const st_map *m = &r->h->map;
    if (src->ids) {
        st_mla_write_renumbered(w, &r->h->edge_sharp, &m->darts, &src->ids->darts, st_value_sharpness_f32);
        st_mla_write_renumbered(w, &r->h->vertex_sharp, &m->verts, &src->ids->verts, st_value_sharpness_f32);
        return;
    }
    st_mla_write(w, &r->h->edge_sharp, &m->darts, st_value_sharpness_f32);
    st_mla_write(w, &r->h->vertex_sharp, &m->verts, st_value_sharpness_f32);
}

/* The compact form (version 4): level 0 alone, then every level's
 * positions; the reader regenerates the topology of levels 1..top (and
 * their sharpness) by the scheme's refinement, exactly as it was built. */
static int level0_of(const st_session_ref *r, st_map *v)
{
    /* Doo-Sabin's levels are in the dual encoding and its level 0 is not a
     * map of its own there: stored whole. */
    if (r->whole_map || r->h->map.face_embedded || !st_hier_regenerable(r->h)) return -1;
    if (r->h->scheme->id == ST_SCHEME_PROGRESSIVE) return -1;   /* its recipe instead (PMRC) */
    return st_map_level0_view(&r->h->map, r->h->regen_end, v);
}

static void w_level0(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    st_map v;
    if (level0_of(r, &v)) { w->failed = 1; return; }   /* chunk_list checked it */
    st_bw_u32(w, r->h->map.top);
    st_map_write(w, &v);
}

static void w_sharp_level0(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    st_map v;
    if (level0_of(r, &v)) { w->failed = 1; return; }
    st_mla e = st_mla_level0_view(&r->h->edge_sharp), x = st_mla_level0_view(&r->h->vertex_sharp);
    st_mla_write(w, &e, &v.darts, st_value_sharpness_f32);
    st_mla_write(w, &x, &v.verts, st_value_sharpness_f32);
}

/* A progressive hierarchy's recipe (version 5): level 0's darts, then each
 * level's splits (st_pm_recipe_encode); the reader replays them
 * (core/progressive/progressive_replay.c). */
static void w_recipe(st_bw *w, const wsrc *src)
{
    st_bw_bytes(w, src->pm, src->pm_len);
}

static void w_positions(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    st_mla_write(w, &r->h->map.pos, &r->h->map.verts, st_value_finite_f64x3);
}

/* Version 3: each level's details up to the last one whose bits are not all
 * zero (at least one), written whole (mode 0) or, when that is smaller, as
 * the list of those not all zero (mode 1: u32 count, then u32 vertex id and
 * the three doubles each): a level of a fresh subdivision holds zeros only,
 * a sculpted one nonzero details where it was sculpted.  The rest read as
 * +0 (st_hier_detail), as st_hier_trim_details trims; -0 is kept. */
static int detail_zero(const double *d)
{
    static const double zero3[3];
    return !memcmp(d, zero3, sizeof zero3);
}

/* Detail of level l of the vertex written as id j (the renumbering's new
 * id, or j itself), +0 past the array and for a free id. */
static const double *detail_of(const wsrc *src, unsigned l, uint32_t j)
{
    static const double zero3[3];
    const st_hier *h = src->r->h;
    uint32_t i = src->ids ? src->ids->verts.old_of[j] : j;
    return i < h->detail_cap[l] ? h->detail[l] + 3 * (size_t)i : zero3;
}

static void w_detail(st_bw *w, const wsrc *src)
{
    const st_hier *h = src->r->h;
    /* Under a renumbering the ids run over the renumbered pool (a free id,
     * ST_NIL in old_of, reads as zero: a free vertex has no detail to keep). */
    uint32_t ids_end = src->ids ? src->ids->verts.pool.end : h->map.verts.end;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        int present = h->detail[l] != NULL;
        st_bw_u8(w, (uint8_t)present);
        if (!present) continue;
        uint32_t n = src->ids ? ids_end : h->detail_cap[l], nonzero = 0;
        while (n > 1 && detail_zero(detail_of(src, l, n - 1))) n--;
        for (uint32_t i = 0; i < n; i++) nonzero += !detail_zero(detail_of(src, l, i));
        /* (the reader bounds a list's cap by the vertex ids: a dense array
         * is bounded by its own bytes) */
        int list = (uint64_t)nonzero * 28 < (uint64_t)n * 24 && n <= ids_end;
        st_bw_u32(w, n);
        st_bw_u8(w, (uint8_t)list);
        if (list) st_bw_u32(w, nonzero);
        for (uint32_t i = 0; i < n; i++) {
            const double *d = detail_of(src, l, i);
            if (list && detail_zero(d)) continue;
            if (list) st_bw_u32(w, i);
            for (int k = 0; k < 3; k++) st_bw_f64(w, d[k]);
        }
    }
}

static void w_params(st_bw *w, const st_adapt_params *p)
{
    static const st_adapt_params none;
    if (!p) p = &none;
    st_bw_u32(w, p->base_level);
    st_bw_u32(w, p->max_level);
    for (int k = 0; k < 3; k++) st_bw_f64(w, p->box_lo[k]);
    for (int k = 0; k < 3; k++) st_bw_f64(w, p->box_hi[k]);
    st_bw_u8(w, p->has_box != 0);
    st_bw_f64(w, p->falloff);
    st_bw_f64(w, p->flatness);
    st_bw_u8(w, p->no_restriction != 0);
}

static void w_store(st_bw *w, const st_adapt_saved *e, uint32_t n)
{
    st_bw_u32(w, n);
    for (uint32_t i = 0; i < n; i++) {
        st_bw_u64(w, e[i].path);
        st_bw_u32(w, e[i].meta);
        for (int k = 0; k < 3; k++) st_bw_f64(w, e[i].d[k]);
    }
}

static int parked_less(const void *x, const void *y)
{
    const st_adapt_saved *a = x, *b = y;
    if (a->path != b->path) return a->path < b->path ? -1 : 1;
    return a->meta < b->meta ? -1 : a->meta > b->meta;
}

/* The parked store under a renumbering: its keys are vertex ids (path =
 * vertex id, core/adapt/adapt.h), translated, and sorted again by (path,
 * meta) as the reader requires (the renumbering keeps the order within a
 * level only).  An entry of a free vertex id cannot be taken by any vertex
 * of the map (a vertex takes its entries when it goes) and is left out. */
static void w_parked_renumbered(st_bw *w, const st_adapt *a, const st_map_renumber *ids)
{
    st_adapt_saved *e = malloc(((size_t)a->nparked + 1) * sizeof *e);
    if (!e) { w->failed = 1; return; }
    uint32_t n = 0;
    for (uint32_t i = 0; i < a->nparked; i++) {
        uint64_t v = a->parked[i].path;
        if (v >= a->h->map.verts.end) continue;   /* (not a vertex id of the map) */
        e[n] = a->parked[i];
        e[n].path = ids->verts.new_of[v];
        n += e[n].path != ST_NIL;
    }
    qsort(e, n, sizeof *e, parked_less);
    w_store(w, e, n);
    free(e);
}

static void w_adapt(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    const st_adapt *a = r->adapt;
    w_store(w, a->saved, a->nsaved);
    if (src->ids) w_parked_renumbered(w, a, src->ids);
    else w_store(w, a->parked, a->nparked);
    st_bw_u32(w, a->base_faces.n);
    /* (darts of level 0: kept by a renumbering, translated all the same) */
    for (uint32_t i = 0; i < a->base_faces.n; i++) {
        uint32_t d = a->base_faces.d[i];
        st_bw_u32(w, src->ids ? src->ids->darts.new_of[d] : d);
    }
    w_params(w, &a->prev);
    st_bw_u8(w, a->has_prev != 0);
    st_bw_u64(w, a->touched);
    st_bw_u64(w, a->forced);
}

static void w_edit(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    unsigned top = r->h->map.top;
    w_params(w, r->box);
    st_bw_u8(w, r->box_on != 0);
    st_bw_u32(w, r->edit_level <= top ? r->edit_level : top);
    st_bw_u32(w, r->display_level <= top ? r->display_level : top);
}

static void w_view(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    const st_session_view *v = r->view;
    for (int k = 0; k < 3; k++) st_bw_f32(w, v->target[k]);
    st_bw_f32(w, v->az);
    st_bw_f32(w, v->el);
    st_bw_f32(w, v->dist);
    st_bw_f32(w, v->fovy);
    st_bw_u32(w, (uint32_t)v->ortho);
    st_bw_f32(w, v->ortho_height);
}

static void w_tool(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    const st_session_tool *t = r->tool;
    st_bw_u32(w, t->tool);
    st_bw_f64(w, t->radius);
    st_bw_f64(w, t->strength);
    st_bw_u32(w, t->falloff);
    st_bw_u32(w, t->mirror);
    st_bw_u32(w, t->show);
}

static void w_base(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    const st_mesh *m = r->base;
    st_bw_u32(w, m->nverts);
    for (size_t i = 0; i < 3 * (size_t)m->nverts; i++) st_bw_f64(w, m->pos[i]);
    st_bw_u32(w, m->nfaces);
    for (uint32_t f = 0; f < m->nfaces; f++) st_bw_u32(w, m->face_off[f + 1] - m->face_off[f]);
    uint32_t nidx = m->nfaces ? m->face_off[m->nfaces] : 0;
    for (uint32_t i = 0; i < nidx; i++) st_bw_u32(w, m->face_idx[i]);
    st_bw_u32(w, m->ncreases);
    for (uint32_t i = 0; i < m->ncreases; i++) {
        st_bw_u32(w, m->crease_v[2 * i]);
        st_bw_u32(w, m->crease_v[2 * i + 1]);
        st_bw_f32(w, m->crease_s[i]);
    }
    st_bw_u32(w, m->ncorners);
    for (uint32_t i = 0; i < m->ncorners; i++) {
        st_bw_u32(w, m->corner_v[i]);
        st_bw_f32(w, m->corner_s[i]);
    }
    st_bw_u32(w, (uint32_t)m->boundary_interp);
}

/* Values up to the last non-zero one (so that load -> save keeps the
 * length). */
static uint32_t mask_len(const st_mask *mk, uint32_t end)
{
    uint32_t n = mk->v ? (mk->cap < end ? mk->cap : end) : 0;
    while (n && mk->v[n - 1] == 0) n--;
    return n;
}

static void w_mask(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    uint32_t n = mask_len(r->mask, r->h->map.verts.end);
    st_bw_u32(w, n);
    for (uint32_t i = 0; i < n; i++) st_bw_f32(w, r->mask->v[i]);
}

static uint32_t off_len(const double *a, uint32_t cap, uint32_t end)
{
    uint32_t n = a ? (cap < end ? cap : end) : 0;
    while (n && a[3 * (size_t)n - 1] == 0 && a[3 * (size_t)n - 2] == 0 && a[3 * (size_t)n - 3] == 0) n--;
    return n;
}

static void w_offsets(st_bw *w, const double *a, uint32_t n)
{
    st_bw_u32(w, n);
    for (size_t i = 0; i < 3 * (size_t)n; i++) st_bw_f64(w, a[i]);
}

/* The kept positions: an entry is three finite numbers, or three NaNs for
 * none (r_offsets reads them so); the NaNs are written as they are. */
static void w_kept_positions(st_bw *w, const double *a, uint32_t n)
{
    st_bw_u32(w, n);
    for (size_t i = 0; i < (size_t)n; i++) {
        const double *e = a + 3 * i;
        if (isnan(e[0]) && isnan(e[1]) && isnan(e[2])) {
            for (int k = 0; k < 3; k++) {
                uint64_t u;
                memcpy(&u, &e[k], 8);
                st_bw_u64(w, u);
            }
        } else {
            for (int k = 0; k < 3; k++) st_bw_f64(w, e[k]);
        }
    }
}

static void w_layers(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    const st_layers *ls = r->layers;
    uint32_t end = src->ids ? src->ids->verts.pool.end : r->h->map.verts.end;
    st_bw_u32(w, ls->active < 0 ? UINT32_MAX : (uint32_t)ls->active);
    st_bw_u32(w, ls->n);
    for (uint32_t i = 0; i < ls->n; i++) {
        const st_layer *y = &ls->v[i];
        uint32_t len = (uint32_t)strlen(y->name);
        st_bw_u32(w, len);
        st_bw_bytes(w, y->name, len);
        st_bw_u32(w, y->level);
        st_bw_f64(w, y->strength);
        st_bw_u8(w, y->hidden != 0);
        w_offsets(w, y->off, off_len(y->off, y->cap, end));
    }
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        if (!st_layers_on_level(ls, l)) continue;
        st_bw_u32(w, l);
        w_offsets(w, ls->base[l], off_len(ls->base[l], ls->base_cap[l], end));
        /* The positions kept without layers (NaN: none), up to the last kept. */
        uint32_t n = ls->bpos[l] ? (ls->bpos_cap[l] < end ? ls->bpos_cap[l] : end) : 0;
        while (n && isnan(ls->bpos[l][3 * (size_t)n - 3])) n--;
        w_kept_positions(w, ls->bpos[l], n);
    }
}

/* The face-varying UVs: the option, the levels that carry them, then per
 * level the UV and value label of every real dart in st_dart_first order. */
/* Whether the UVs of levels 1..top can be left to the reader: the levels
 * are regenerated (LVL0) and the UVs refine after the topology, level by
 * level from level 0, as they were built (st_fvar_refine_levels). */
static int fvar_regenerable(const st_session_ref *r)
{
    st_map v;
    const st_fvar *f = r->h->fvar;
    int rules = st_fvar_rules_of(r->h->scheme);
    return !level0_of(r, &v) && f->levels == r->h->map.top + 1 && rules >= 0 && rules != ST_FVAR_STENCIL;
}

static void w_fvar(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    const st_hier *h = r->h;
    const st_fvar *f = h->fvar;
    unsigned levels = f->levels <= h->map.top + 1 ? f->levels : h->map.top + 1;
    if (fvar_regenerable(r)) levels = 1;
    st_bw_u32(w, (uint32_t)f->interp);
    st_bw_u32(w, levels);
    /* Under a renumbering the darts come in the order the renumbered map
     * enumerates them (the reader's order): a map view holding only the
     * renumbered dart pool, which is all st_dart_first reads. */
    st_map order;
    if (src->ids) {
        memset(&order, 0, sizeof order);
        order.darts = src->ids->darts.pool;
    }
    const st_map *om = src->ids ? &order : &h->map;
    for (unsigned l = 0; l < levels; l++) {
        st_dart_iter it;
        for (uint32_t j = st_dart_first(om, l, &it); j != ST_NIL; j = st_dart_next(om, l, &it)) {
            uint32_t d = src->ids ? src->ids->darts.old_of[j] : j;
            if (st_is_boundary(&h->map, d)) continue;
            int in = d < f->lv[l].cap;
            const double *uv = in ? st_fvar_uv_at(&f->lv[l], d) : NULL;
            st_bw_f64(w, in ? uv[0] : 0);
            st_bw_f64(w, in ? uv[1] : 0);
            st_bw_u32(w, in ? st_fvar_label_at(&f->lv[l], d) : 0);
        }
    }
}

/* The base mesh's UVs (mesh.h: uv, face_uv parallel to face_idx). */
static void w_base_uv(st_bw *w, const wsrc *src)
{
    const st_session_ref *r = src->r;
    const st_mesh *m = r->base;
    st_bw_u32(w, m->nuvs);
    for (size_t i = 0; i < 2 * (size_t)m->nuvs; i++) st_bw_f64(w, m->uv[i]);
    uint32_t nidx = m->nfaces ? m->face_off[m->nfaces] : 0;
    for (uint32_t i = 0; i < nidx; i++) st_bw_u32(w, m->face_uv[i]);
}

/* The reference a nested HD image is made from (hd_image, below). */
static st_session_ref hd_ref(const st_session_ref *r)
{
    st_session_ref n = { .h = r->hd, .adapt = r->hd_adapt, .whole_map = 1, .layers = r->hd_layers };
    return n;
}

static void w_hd(st_bw *w, const wsrc *src)
{
    st_bw_u32(w, src->r->hd_from);
    st_bw_bytes(w, src->hd_img, src->hd_len);   /* made by hd_image before the counting pass */
}

typedef struct chunk_def { uint32_t tag; chunk_fn fn; } chunk_def;
/* Every tag at most once: HIER, MAP or LVL0 and POSN, SHRP DETL ADPT EDIT
 * VIEW BASE mask tool layr FVAR BUVS hdlv. */
#define ST_SESSION_MAX_CHUNKS 15

/* The chunks of src's reference, in file order. */
static unsigned chunk_list(const wsrc *src, chunk_def out[ST_SESSION_MAX_CHUNKS])
{
    const st_session_ref *r = src->r;
    unsigned n = 0;
    out[n++] = (chunk_def){ TAG_HIER, w_hier };
    st_map v;
    if (src->pm) {
        out[n++] = (chunk_def){ TAG_PMRC, w_recipe };
        out[n++] = (chunk_def){ TAG_POSN, w_positions };
    } else if (!level0_of(r, &v)) {
        out[n++] = (chunk_def){ TAG_LVL0, w_level0 };
        if (r->h->has_sharpness) out[n++] = (chunk_def){ TAG_SHRP, w_sharp_level0 };
        /* Level 0's UVs before the positions: the reader refines them on a
         * second thread while it reads the positions (session_read.c). */
        if (r->h->fvar && fvar_regenerable(r)) out[n++] = (chunk_def){ TAG_FVAR, w_fvar };
        out[n++] = (chunk_def){ TAG_POSN, w_positions };
    } else {
        out[n++] = (chunk_def){ TAG_MAP, w_map };
        if (r->h->has_sharpness) out[n++] = (chunk_def){ TAG_SHRP, w_sharp };
    }
    out[n++] = (chunk_def){ TAG_DETL, w_detail };
    if (r->adapt) out[n++] = (chunk_def){ TAG_ADPT, w_adapt };
    out[n++] = (chunk_def){ TAG_EDIT, w_edit };
    if (r->view) out[n++] = (chunk_def){ TAG_VIEW, w_view };
    if (r->base) out[n++] = (chunk_def){ TAG_BASE, w_base };
    if (r->mask && mask_len(r->mask, r->h->map.verts.end)) out[n++] = (chunk_def){ TAG_MASK, w_mask };
    if (r->tool) out[n++] = (chunk_def){ TAG_TOOL, w_tool };
    if (r->layers && r->layers->n)
        out[n++] = (chunk_def){ st_layers_on_level(r->layers, 0) ? TAG_LAY0 : TAG_LAYR, w_layers };
    if (r->h->fvar && !fvar_regenerable(r)) out[n++] = (chunk_def){ TAG_FVAR, w_fvar };   /* else above */
    if (r->base && r->base->face_uv) out[n++] = (chunk_def){ TAG_BUVS, w_base_uv };
    /* Last: after every chunk of the main hierarchy, which the reader
     * compares it with. */
    if (r->hd) out[n++] = (chunk_def){ TAG_HDLV, w_hd };
    return n;
}


static int check_ref(const st_session_ref *r, st_error *err);

/* The HD hierarchy: what the reader checks (session_read.c, r_hd), so that
 * nothing is written that would not load again. */
static int check_hd(const st_session_ref *r, st_error *err)
{
    const st_hier *h = r->h, *hd = r->hd;
    if (!r->hd_adapt || r->hd_adapt->h != hd)
        return st_fail(err, ST_ERR_INVALID, "session: the HD hierarchy has no adaptive state of its own");
    if (hd->scheme != h->scheme)
        return st_fail(err, ST_ERR_INVALID, "session: the HD hierarchy's scheme is %s, the model's %s",
                       hd->scheme ? hd->scheme->name : "none", h->scheme->name);
    if (r->hd_from != h->map.top || hd->map.top < r->hd_from)
        return st_fail(err, ST_ERR_INVALID, "session: the HD hierarchy starts at level %u, the model's top is %u", r->hd_from, h->map.top);
    for (unsigned l = 0; l <= r->hd_from; l++)
        if (hd->map.darts.live[l] != h->map.darts.live[l] || hd->map.verts.live[l] != h->map.verts.live[l])
            return st_fail(err, ST_ERR_INVALID, "session: the HD hierarchy's level %u is not the model's", l);
    st_session_ref n = hd_ref(r);
    return check_ref(&n, err);
}

static int check_ref(const st_session_ref *r, st_error *err)
{
    if (!r || !r->h || !r->h->scheme) return st_fail(err, ST_ERR_INVALID, "session: no hierarchy to save");
    const st_hier *h = r->h;
    const st_map *m = &h->map;
    for (uint32_t i = 0; i < m->ndart_attrs; i++)
        if (m->dart_attrs[i] != &h->edge_sharp)
            return st_fail(err, ST_ERR_INVALID, "session: the map carries a per-dart attribute the session format does not know");
    for (uint32_t i = 0; i < m->nvert_attrs; i++)
        if (m->vert_attrs[i] != &h->vertex_sharp)
            return st_fail(err, ST_ERR_INVALID, "session: the map carries a per-vertex attribute the session format does not know");
    if (r->adapt && r->adapt->h != h)
        return st_fail(err, ST_ERR_INVALID, "session: the adaptive state belongs to another hierarchy");
    if (r->base && st_mesh_check("base mesh", r->base, err)) return err ? err->code : ST_ERR_INVALID;
    if (r->hd) return check_hd(r, err);
    return ST_OK;
}

/* What a chunk holds, for messages. */
static const char *chunk_words(uint32_t tag)
{
    switch (tag) {
    case TAG_MAP: case TAG_POSN: return "positions";
    case TAG_LVL0: return "positions of level 0";
    case TAG_PMRC: return "progressive levels";
    case TAG_SHRP: return "sharpness values";
    case TAG_DETL: return "details";
    case TAG_ADPT: return "adaptive state";
    case TAG_EDIT: return "interest box";
    case TAG_VIEW: return "view";
    case TAG_BASE: return "base mesh";
    case TAG_MASK: return "mask";
    case TAG_TOOL: return "tool settings";
    case TAG_LAY0: case TAG_LAYR: return "sculpt layers";
    case TAG_FVAR: return "UVs";
    case TAG_BUVS: return "base mesh's UVs";
    case TAG_HDLV: return "HD hierarchy";
    default: return "values";
    }
}

/* The chunks of r and their lengths, by a counting pass.  Refuses a model
 * holding a value the reader would refuse (a position or detail an edit
 * or a synthesis carried past the double range, say): the file would not
 * load again, so nothing is written. */
typedef struct chunk_plan {
    chunk_def c[ST_SESSION_MAX_CHUNKS];
    uint64_t len[ST_SESSION_MAX_CHUNKS];
    unsigned n;
    uint64_t total;
} chunk_plan;


static int plan_chunks(const wsrc *src, chunk_plan *pl, st_error *err)
{
    const st_session_ref *r = src->r;
    if (r->tool && st_session_tool_refusal(r->tool))
        return st_fail(err, ST_ERR_INVALID, "session: bad %s in the tool settings; nothing was written", st_session_tool_refusal(r->tool));
    pl->n = chunk_list(src, pl->c);
    pl->total = HEADER_BYTES + TRAILER_BYTES;
    st_bw *cnt = malloc(sizeof *cnt);
    if (!cnt) return st_fail(err, ST_ERR_MEMORY, "session: out of memory");
    for (unsigned i = 0; i < pl->n; i++) {
        st_bw_init_count(cnt);
        pl->c[i].fn(cnt, src);
        if (cnt->refused_value) {
            free(cnt);
            return st_fail(err, ST_ERR_INVALID, "session: a number in the %s is not finite (an edit overflowed?); nothing was written",
                           chunk_words(pl->c[i].tag));
        }
        pl->len[i] = cnt->total;
        pl->total += CHUNK_HEAD + pl->len[i];
    }
    free(cnt);
    return ST_OK;
}

/* Writes the whole file to w, as planned. */
static void write_all(st_bw *w, const wsrc *src, const chunk_plan *pl)
{
    unsigned char head[HEADER_BYTES];
    memcpy(head, ST_SESSION_MAGIC, 8);
    uint32_t version = ST_SESSION_VERSION;
    for (int k = 0; k < 4; k++) head[8 + k] = (unsigned char)(version >> (8 * k));
    memset(head + 12, 0, 4);
    for (int k = 0; k < 8; k++) head[16 + k] = (unsigned char)(pl->total >> (8 * k));
    w->progress_total = pl->total;
    uint32_t hc = st_crc32(0, head, 24);
    for (int k = 0; k < 4; k++) head[24 + k] = (unsigned char)(hc >> (8 * k));
    st_bw_bytes(w, head, sizeof head);
    for (unsigned i = 0; i < pl->n; i++) {
        if (w->failed) return;   /* a write failed or the save was cancelled: the rest is not wanted */
        uint64_t before = w->total;
        st_bw_u32(w, pl->c[i].tag);
        st_bw_u64(w, pl->len[i]);
        pl->c[i].fn(w, src);
        if (w->total - before != CHUNK_HEAD + pl->len[i]) w->failed = 1; /* cannot happen: same writer twice */
    }
    st_bw_flush(w);
    uint32_t crc = st_bw_checksum(w);   /* version 4: XXH3 (st_session_checksum) */
    unsigned char t[4];
    for (int k = 0; k < 4; k++) t[k] = (unsigned char)(crc >> (8 * k));
    st_bw_bytes(w, t, 4);
    st_bw_flush(w);
}

static int write_mem(const wsrc *src, void **data, size_t *size, st_error *err)
{
    *data = NULL;
    *size = 0;
    chunk_plan pl;
    int rc = plan_chunks(src, &pl, err);
    if (rc) return rc;
    st_bw *w = malloc(sizeof *w);
    if (!w) return st_fail(err, ST_ERR_MEMORY, "session: out of memory");
    st_bw_init_mem(w);
    write_all(w, src, &pl);
    if (w->failed) {
        free(w->out);
        st_bw_free(w);
        free(w);
        return st_fail(err, ST_ERR_MEMORY, "session: out of memory");
    }
    *data = w->out;
    *size = w->outlen;
    st_bw_free(w);
    free(w);
    return ST_OK;
}

/* The HD hierarchy as a nested session image (the reference holding the
 * HD hierarchy and its adaptive state, nothing else), made by this very
 * writer so that the format and its checks are those of a session.  Its
 * ids are written renumbered (core/map/renumber_internal.h): the live
 * ones only, the model's levels 0..hd_from keeping theirs, so that the
 * image's bytes follow the faces stored and not the ids the box's
 * coarsenings freed.
 * The document's hierarchy is only read: the renumbering is two tables
 * beside it (4 bytes per id each way), not a copy of the map. */
/* One per-vertex array (3 doubles per id, `fill` past its end) under the
 * renumbering v: entry j is the old id old_of[j]'s. */
static double *renumber3(const double *a, uint32_t cap, const st_pool_renumber *v, double fill, int *oom)
{
    if (!a) return NULL;
    uint32_t end = v->pool.end;
    double *q = malloc(3 * (size_t)(end ? end : 1) * sizeof *q);
    if (!q) { *oom = 1; return NULL; }
    for (uint32_t j = 0; j < end; j++) {
        uint32_t o = v->old_of[j];
        for (int k = 0; k < 3; k++) q[3 * (size_t)j + k] = o != ST_NIL && o < cap ? a[3 * (size_t)o + k] : fill;
    }
    return q;
}

/* The HD levels' sculpt layers with their vertex arrays under the
 * image's renumbering (the offsets, B_l and P0 index vertex ids).  -1:
 * out of memory (dst freed). */
static int renumber_layers(const st_layers *src, const st_pool_renumber *v, st_layers *dst)
{
    st_layers_init(dst);
    int oom = 0;
    dst->v = malloc((size_t)(src->n ? src->n : 1) * sizeof *dst->v);
    if (!dst->v) return -1;
    dst->cap = src->n;
    dst->active = src->active;
    for (uint32_t i = 0; i < src->n; i++) {
        dst->v[i] = src->v[i];
        dst->v[i].off = renumber3(src->v[i].off, src->v[i].cap, v, 0, &oom);
        dst->v[i].cap = dst->v[i].off ? v->pool.end : 0;
        dst->n = i + 1;
    }
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        dst->base[l] = renumber3(src->base[l], src->base_cap[l], v, 0, &oom);
        dst->base_cap[l] = dst->base[l] ? v->pool.end : 0;
        dst->bpos[l] = renumber3(src->bpos[l], src->bpos_cap[l], v, NAN, &oom);
        dst->bpos_cap[l] = dst->bpos[l] ? v->pool.end : 0;
    }
    if (oom) st_layers_free(dst);
    return oom ? -1 : 0;
}

static int hd_image(const st_session_ref *r, void **img, size_t *len, st_error *err)
{
    st_map_renumber ids;
    if (st_map_renumber_make(&r->hd->map, r->hd_from, &ids)) return st_fail(err, ST_ERR_MEMORY, "session: out of memory");
    st_session_ref n = hd_ref(r);
    st_layers layers;
    st_layers_init(&layers);
    if (n.layers && n.layers->n) {
        if (renumber_layers(n.layers, &ids.verts, &layers)) {
            st_map_renumber_free(&ids);
            return st_fail(err, ST_ERR_MEMORY, "session: out of memory");
        }
        n.layers = &layers;
    }
    wsrc nested = { .r = &n, .ids = &ids };
    st_error e;
    int rc = write_mem(&nested, img, len, &e);
    st_map_renumber_free(&ids);
    st_layers_free(&layers);
    /* A value the reader would refuse is reported as for the main
     * hierarchy (plan_chunks); anything else is out of memory. */
    if (rc == ST_ERR_INVALID)
        return st_fail(err, rc, "session: a number in the %s is not finite (an edit overflowed?); nothing was written",
                       chunk_words(TAG_HDLV));
    if (rc) return st_fail(err, ST_ERR_MEMORY, "session: out of memory");
    return ST_OK;
}

/* A progressive hierarchy as its build left it is stored as its recipe
 * (PMRC): the bytes the build or the reader kept (st_hier.pm_recipe), else
 * read back from the map; anything else, or out of memory, is stored
 * whole. */
static void recipe_of(const st_session_ref *r, wsrc *src)
{
    const st_hier *h = r->h;
    if (r->whole_map || h->has_sharpness || h->scheme->id != ST_SCHEME_PROGRESSIVE || !st_hier_regenerable(h)) return;
    if (h->pm_recipe) {
        src->pm = h->pm_recipe;
        src->pm_len = h->pm_recipe_len;
        return;
    }
    st_pm_recipe pm;
    if (st_progressive_recipe(h, &pm)) return;
    size_t n = st_pm_recipe_encode(&pm, NULL);
    unsigned char *b = malloc(n);
    if (b) {
        st_pm_recipe_encode(&pm, b);
        src->pm = src->pm_owned = b;
        src->pm_len = n;
    }
    st_pm_recipe_free(&pm);
}

static void release(wsrc *src)
{
    free((void *)src->hd_img);
    free(src->pm_owned);
    src->hd_img = NULL;
    src->pm = src->pm_owned = NULL;
}

/* Checks r and makes what the chunk writers read (wsrc); the caller
 * releases it. */
static int prepare(const st_session_ref *r, wsrc *src, st_error *err)
{
    memset(src, 0, sizeof *src);
    src->r = r;
    int rc = check_ref(r, err);
    if (!rc) recipe_of(r, src);
    if (!rc && r->hd) {
        void *img = NULL;
        rc = hd_image(r, &img, &src->hd_len, err);
        src->hd_img = img;
    }
    return rc;
}

int st_session_write_mem(const st_session_ref *r, void **data, size_t *size, st_error *err)
{
    *data = NULL;
    *size = 0;
    wsrc src;
    int rc = prepare(r, &src, err);
    if (!rc) rc = write_mem(&src, data, size, err);
    release(&src);
    return rc;
}

int st_session_save_ref(const char *path, const st_session_ref *r, st_error *err)
{
    return st_session_save_ref_progress(path, r, NULL, NULL, err);
}

int st_session_save_ref_progress(const char *path, const st_session_ref *r, int (*progress)(void *ctx, double fraction),
                                 void *ctx, st_error *err)
{
    chunk_plan pl;
    wsrc src;
    int rc = prepare(r, &src, err);
    if (!rc) rc = plan_chunks(&src, &pl, err);
    if (rc) {
        release(&src);
        if (err) {
            char msg[sizeof err->msg];
            snprintf(msg, sizeof msg, "%s", err->msg);
            st_fail(err, rc, "%s: %s", path, msg);
        }
        return rc;
    }
    st_bw *w = malloc(sizeof *w);
    if (!w) { release(&src); return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", path); }
    st_afile af;
    rc = st_afile_open(&af, path, err);
    if (rc) { free(w); release(&src); return rc; }
    st_bw_init_file(w, af.f);
    /* Test hook (tests/cli/cli_session.sh): slow the save down so that a test
     * can kill it in the middle. */
    const char *slow = getenv("STRATA_SAVE_SLOWDOWN");
    if (slow) w->slow_us = strtol(slow, NULL, 10);
    w->progress = progress;
    w->progress_ctx = ctx;
    write_all(w, &src, &pl);
    release(&src);
    int failed = w->failed, cancelled = w->cancelled;
    st_bw_free(w);
    free(w);
    if (failed) {
        int e = errno;
        st_afile_abort(&af);
        if (cancelled) return st_fail(err, ST_ERR_INVALID, "%s: cancelled (the file is as it was)", path);
        return st_fail(err, ST_ERR_IO, "%s: write error: %s", path, strerror(e ? e : EIO));
    }
    return st_afile_commit(&af, err);
}

int st_session_save(const char *path, const st_session *s, st_error *err)
{
    st_session_ref r = st_session_ref_of(s);
    return st_session_save_ref(path, &r, err);
}
