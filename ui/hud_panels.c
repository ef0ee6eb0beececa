/* The modeller's overlay, drawn with the HUD primitives of hud.c: the
 * information panel, the status line and questions, the F1 help (rows
 * generated from the action table, actions.c), the "working..." panel of a
 * long operation, the brush circle, the selection rectangle and the
 * interest box's handles. */
#include "window.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "actions.h"
#include "gui.h"

static const float C_TEXT[4] = { 0.08f, 0.09f, 0.12f, 1 };
static const float C_DIM[4] = { 0.30f, 0.32f, 0.38f, 1 };
static const float C_ERR[4] = { 0.80f, 0.05f, 0.05f, 1 };
static const float C_OK[4] = { 0.05f, 0.40f, 0.15f, 1 };
static const float C_PANEL[4] = { 1, 1, 1, 0.6f };
static const float C_DARK[4] = { 0.10f, 0.11f, 0.14f, 0.88f };
static const float C_WHITE[4] = { 1, 1, 1, 1 };
static const float C_BRUSH[4] = { 0.95f, 0.35f, 0.10f, 0.9f };
static const float C_RECT[4] = { 0.10f, 0.30f, 0.85f, 0.9f };
static const float C_RECT_FILL[4] = { 0.10f, 0.30f, 0.85f, 0.12f };

/* Text scale: the font's 7-pixel glyphs enlarged, less in small windows. */
static float hud_scale = 1.6f;
#define HUD_SCALE hud_scale
#define HUD_LINE (12 * HUD_SCALE)

/* The "working..." panel of a long operation (reads nothing of the
 * document: a worker thread may own it). */
void st_app_draw_working(st_app *a)
{
    st_hud *u = &a->hud;
    if (!a->working[0] || st_gui_shown()) return;   /* the GUI's progress window says it */
    float sc = 2 * HUD_SCALE;
    float w = st_hud_text_width(a->working, sc);
    if (w > (float)a->fb_w - 48) { sc *= ((float)a->fb_w - 48) / w; w = st_hud_text_width(a->working, sc); }
    float h = 12 * sc, x = 0.5f * ((float)a->fb_w - w), y = 0.5f * ((float)a->fb_h - h);
    st_hud_rect(u, x - 20, y - 16, x + w + 20, y + h + 8, C_DARK);
    st_hud_text(u, x, y, sc, C_WHITE, a->working);
}

/* The F1 help's columns, at scale 1: long keys or descriptions wrap. */
#define HELP_KEYS_W 210.0f
#define HELP_WHAT_W 290.0f

/* Copies text into out (n bytes), replacing by '\n' the spaces where a
 * line would get wider than maxw at scale 1; returns the number of lines. */
static int wrap_text(const char *text, float maxw, char *out, size_t n)
{
    snprintf(out, n, "%s", text);
    int lines = 1;
    char *line = out, *last_space = NULL;
    for (char *p = out; *p; p++) {
        if (*p != ' ') continue;
        *p = 0;
        float w = st_hud_text_width(line, 1);
        *p = ' ';
        if (w > maxw && last_space) {
            *last_space = '\n';
            line = last_space + 1;
            lines++;
        }
        last_space = p;
    }
    if (st_hud_text_width(line, 1) > maxw && last_space && last_space + 1 > line) {
        *last_space = '\n';
        lines++;
    }
    return lines;
}

/* Splits the help's rows into columns of at most per lines, a heading never
 * last in a column; returns the number of columns, their first rows in
 * start (at most ncap). */
static unsigned help_columns(const int *lines, const st_help_row *rows, unsigned n, int per, unsigned *start,
                             unsigned ncap)
{
    unsigned ncol = 0, i = 0;
    while (i < n && ncol < ncap) {
        start[ncol++] = i;
        unsigned end = i;
        int used = 0;
        while (end < n && (end == i || used + lines[end] <= per)) used += lines[end++];
        if (end < n && end - i > 1 && rows[end - 1].heading) end--;
        i = end;
    }
    return i < n ? ncap + 1 : ncol;
}

/* The F1 help: the rows generated from the action table (actions.c) in one
 * to three columns, whichever fits the largest text in the window. */
static void draw_help(st_app *a)
{
    static const float C_HEADING[4] = { 0.55f, 0.75f, 1.00f, 1 };
    static st_help_row rows[ST_HELP_MAX_ROWS];
    static char keys[ST_HELP_MAX_ROWS][192], what[ST_HELP_MAX_ROWS][192];
    static int lines[ST_HELP_MAX_ROWS];
    st_hud *u = &a->hud;
    unsigned n = st_help_rows(rows, ST_HELP_MAX_ROWS);
    if (n > ST_HELP_MAX_ROWS) n = ST_HELP_MAX_ROWS;
    float keysw = 0, whatw = 0;    /* column widths at scale 1 */
    int total = 0;
    for (unsigned i = 0; i < n; i++) {
        int lk = wrap_text(rows[i].heading ? rows[i].heading : rows[i].keys, HELP_KEYS_W, keys[i], sizeof keys[i]);
        int lw = wrap_text(rows[i].what ? rows[i].what : "", HELP_WHAT_W, what[i], sizeof what[i]);
        lines[i] = lk > lw ? lk : lw;
        total += lines[i];
        keysw = fmaxf(keysw, st_hud_text_width(keys[i], 1));
        whatw = fmaxf(whatw, st_hud_text_width(what[i], 1));
    }
    const float gap = 24, colw = keysw + 16 + whatw;
    unsigned start[4] = { 0 }, ncol = 1;
    int best_per = total;
    float s = 0;
    for (int want = 1; want <= 3; want++) {
        int per = (total + want - 1) / want;
        unsigned st[4];
        unsigned nc;
        while ((nc = help_columns(lines, rows, n, per, st, (unsigned)want)) > (unsigned)want) per++;
        float sw = ((float)a->fb_w - 48 - gap * (float)(nc - 1)) / (colw * (float)nc);
        float sh = ((float)a->fb_h - 40) / (12.0f * (float)(per + 2));
        float sc = fminf(HUD_SCALE, fminf(sw, sh));
        if (sc > s + 1e-4f) { s = sc; ncol = nc; best_per = per; memcpy(start, st, sizeof st); }
    }
    float lh = 12 * s, x0 = 24;
    float h = (float)(best_per + 1) * lh;
    float y0 = 0.5f * ((float)a->fb_h - h);
    float w = (float)ncol * colw * s + (float)(ncol - 1) * gap;
    st_hud_rect(u, x0 - 12, y0 - 10, x0 + w + 12, y0 + h + 4, C_DARK);
    st_hud_text(u, x0, y0, s, C_BRUSH, "Key bindings (F1 closes)");
    for (unsigned c = 0; c < ncol; c++) {
        unsigned end = c + 1 < ncol ? start[c + 1] : n;
        float x = x0 + (float)c * (colw * s + gap), y = y0 + lh;
        for (unsigned i = start[c]; i < end; i++) {
            st_hud_text(u, x, y, s, rows[i].heading ? C_HEADING : C_BRUSH, keys[i]);
            if (!rows[i].heading) st_hud_text(u, x + (keysw + 16) * s, y, s, C_WHITE, what[i]);
            y += (float)lines[i] * lh;
        }
    }
}

void st_app_draw_hud(st_app *a)
{
    st_hud *u = &a->hud;
    st_doc *d = &a->doc;
    hud_scale = a->fb_h < 600 || a->fb_w < 800 ? 1.2f : 1.6f;
    char line[10][256], t1[32], t2[32];
    int n = 0;
    /* The GUI's side panel shows all this (ui/gui.cc). */
    int panel = !st_gui_shown();
    if (!panel) {
    } else if (d->loaded) {
        uint64_t faces = 0, verts = 0;
        st_doc_display_counts(d, &faces, &verts);
        snprintf(line[n++], 256, "%s   %s", st_path_base(d->path), d->scheme ? d->scheme->name : "?");
        char lv[48];
        snprintf(line[n++], 256, "%s   editing %s%u   displayed %s%u", st_levels_phrase(d->h.map.top, lv, sizeof lv),
                 d->hd_level ? "HD " : "", st_doc_sculpt_level(d), st_doc_display_adaptive(d) ? "adaptive " : "",
                 st_doc_display_map_level(d));
        snprintf(line[n++], 256, "faces %llu   vertices %llu   editing-level vertices %u",
                 (unsigned long long)faces, (unsigned long long)verts, a->r.has_cage ? a->r.cage.nverts : 0);
        if (a->tool == ST_TOOL_SELECT)
            snprintf(line[n++], 256, "tool select/move   selected %u", d->nsel);
        else {
            char sym[16] = "", fall[32] = "";
            if (d->brush.mirror_x || d->brush.mirror_y || d->brush.mirror_z)
                snprintf(sym, sizeof sym, "   mirror %s%s%s", d->brush.mirror_x ? "X" : "", d->brush.mirror_y ? "Y" : "",
                         d->brush.mirror_z ? "Z" : "");
            if (d->brush.falloff != ST_FALLOFF_SMOOTH)
                snprintf(fall, sizeof fall, "   falloff %s", st_falloff_name(d->brush.falloff));
            snprintf(line[n++], 256, "tool brush %s   radius %.3g   strength %.2f%s%s%s   selected %u",
                     st_brush_name(a->tool), d->brush.radius, d->brush.strength, fall, sym,
                     d->brush.invert ? "   inverted" : "", d->nsel);
        }
        if (d->box_on)
            snprintf(line[n++], 256, "box (%.2f %.2f %.2f)-(%.2f %.2f %.2f)   levels %u..%u",
                     d->box.box_lo[0], d->box.box_lo[1], d->box.box_lo[2], d->box.box_hi[0], d->box.box_hi[1],
                     d->box.box_hi[2], d->box.base_level, d->box.max_level);
        else
            snprintf(line[n++], 256, "box off (I)");
        snprintf(line[n++], 256, "undo %u/%u   %s", d->undo_pos, d->nundo, a->cc.cam.ortho ? "ortho" : "persp");
    } else {
        snprintf(line[n++], 256, "no model: drop a mesh file on the window");
    }
    char t3[32];
    if (panel) snprintf(line[n++], 256, "frame %s   last update: geometry %s + buffers %s   F1 help", st_app_fmt_ms(a, a->frame_ms, t1, sizeof t1),
             st_app_fmt_ms(a, d->loaded ? d->last_update_ms : 0, t2, sizeof t2), st_app_fmt_ms(a, a->update_ms, t3, sizeof t3));
    float wmax = 0;
    for (int i = 0; i < n; i++) {
        float w = st_hud_text_width(line[i], HUD_SCALE);
        if (w > wmax) wmax = w;
    }
    if (n) st_hud_rect(u, 0, 0, wmax + 16, 8 + n * HUD_LINE, C_PANEL);
    for (int i = 0; i < n; i++) st_hud_text(u, 8, 6 + i * HUD_LINE, HUD_SCALE, i == 0 ? C_TEXT : C_DIM, line[i]);

    /* Status line and questions at the bottom. */
    const char *msg = a->msg;
    char ask[256];
    if (a->quit_asking) {
        snprintf(ask, sizeof ask, "Save the changes before quitting? S: save, D: don't save, any other key: cancel");
        msg = ask;
    } else if (a->pending_scheme) {
        snprintf(ask, sizeof ask, "Change the scheme to %s? The hierarchy is rebuilt, details are lost. Y: yes, K: next scheme, N: no",
                 a->pending_scheme);
        msg = ask;
    }
    /* With the GUI, messages are its notifications (gui.cc) and the scheme
     * question its window. */
    if (msg[0] && panel) {
        /* Wrapped at spaces to the window's width (long error messages). */
        char lines[4][ST_MSG_LEN];
        int nl = 0;
        float maxw = (float)a->fb_w - 16, wmax = 0;
        const char *p = msg;
        while (*p && nl < 4) {
            size_t n = strlen(p), cut = n;
            if (st_hud_text_width(p, HUD_SCALE) > maxw && nl < 3) {
                /* The longest prefix ending at a space that fits. */
                char tmp[ST_MSG_LEN];
                size_t best = 0;
                for (size_t i = 1; i < n && i < sizeof tmp; i++) {
                    if (p[i] != ' ') continue;
                    memcpy(tmp, p, i);
                    tmp[i] = 0;
                    if (st_hud_text_width(tmp, HUD_SCALE) > maxw) break;
                    best = i;
                }
                if (best) cut = best;
            }
            if (cut >= sizeof lines[0]) cut = sizeof lines[0] - 1;
            memcpy(lines[nl], p, cut);
            lines[nl][cut] = 0;
            float w = st_hud_text_width(lines[nl], HUD_SCALE);
            if (w > wmax) wmax = w;
            nl++;
            p += cut;
            while (*p == ' ') p++;
        }
        float y = (float)a->fb_h - nl * HUD_LINE - 6;
        st_hud_rect(u, 0, y - 4, wmax + 16, (float)a->fb_h, C_PANEL);
        for (int i = 0; i < nl; i++)
            st_hud_text(u, 8, y + i * HUD_LINE, HUD_SCALE, a->pending_scheme || a->quit_asking ? C_TEXT : a->msg_error ? C_ERR : C_OK, lines[i]);
    }

    if (a->help && panel) draw_help(a);   /* with the GUI: its Keys window */

    st_app_draw_working(a);
}

void st_app_draw_overlays(st_app *a)
{
    st_hud *u = &a->hud;
    if (a->op == ST_OP_RECT) {
        float x0 = (float)a->op_x0, y0 = (float)a->op_y0, x1 = (float)a->mx, y1 = (float)a->my;
        st_hud_rect(u, fminf(x0, x1), fminf(y0, y1), fmaxf(x0, x1), fmaxf(y0, y1), C_RECT_FILL);
        st_hud_line(u, x0, y0, x1, y0, 1.5f, C_RECT);
        st_hud_line(u, x1, y0, x1, y1, 1.5f, C_RECT);
        st_hud_line(u, x1, y1, x0, y1, 1.5f, C_RECT);
        st_hud_line(u, x0, y1, x0, y0, 1.5f, C_RECT);
    }
    if (a->tool != ST_TOOL_SELECT && a->doc.loaded) {
        /* The brush circle: its radius projected at the surface point under
         * the cursor (or at the grab centre during a grab stroke). */
        const double *p = a->op == ST_OP_STROKE && a->tool == ST_BRUSH_GRAB ? a->stroke_pos : a->brush_pos;
        if (a->brush_hit || a->op == ST_OP_STROKE) {
            double s[2];
            double px = st_camctl_pixel_size(&a->cc, a->fb_w, a->fb_h, p);
            float rad = (float)(a->doc.brush.radius / (px > 0 ? px : 1));
            if (st_camctl_project(&a->cc, a->fb_w, a->fb_h, p, s, NULL))
                st_hud_circle(u, (float)s[0], (float)s[1], rad, 2, C_BRUSH);
            /* The mirrored dabs of the symmetry (core/sculpt/sculpt.c). */
            unsigned sym = (a->doc.brush.mirror_x ? 1u : 0) | (a->doc.brush.mirror_y ? 2u : 0) |
                           (a->doc.brush.mirror_z ? 4u : 0);
            for (unsigned m = 1; m < 8; m++) {
                if (m & ~sym) continue;
                double q[3];
                for (int k = 0; k < 3; k++) q[k] = m >> k & 1 ? -p[k] : p[k];
                if (st_camctl_project(&a->cc, a->fb_w, a->fb_h, q, s, NULL))
                    st_hud_circle(u, (float)s[0], (float)s[1], rad, 1, C_BRUSH);
            }
        } else {
            st_hud_circle(u, (float)a->mx, (float)a->my, 30, 1, C_DIM);
        }
    }
}

void st_app_draw_handles(st_app *a)
{
    static const float c[4] = { 0.10f, 0.45f, 0.90f, 0.95f }, hot[4] = { 0.35f, 0.95f, 1.00f, 1 };
    if (!a->doc.loaded || !a->doc.box_on) return;
    for (int k = 0; k < 7; k++) {
        double p[3], s[2];
        st_box_handle_pos(&a->doc.box, k, p);
        if (!st_camctl_project(&a->cc, a->fb_w, a->fb_h, p, s, NULL)) continue;
        float r = k == 6 ? 6.0f : 4.5f;
        const float *col = k == a->box_handle ? hot : c;
        if (k == 6) st_hud_circle(&a->hud, (float)s[0], (float)s[1], r, 2.5f, col);
        else st_hud_rect(&a->hud, (float)s[0] - r, (float)s[1] - r, (float)s[0] + r, (float)s[1] + r, col);
    }
}
