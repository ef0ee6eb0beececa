/* The window's side panel (Dear ImGui): the model and its levels, the
 * interest box, the brush (tool, radius, strength, falloff, symmetry,
 * auto-smooth, stroke), the mask, sculpt layers, the filter of a
 * progressive model and the timings; a drag of its left edge sets its
 * width (a preference).  Its widgets are named for tests/cli/cli_gui_xdotool.sh
 * (STRATA_GUI_PROBE). */
#include "gui_internal.h"

extern "C" {
#include "actions.h"
#include "prefs.h"
#include "core/multires/hier.h"
#include "core/progressive/scheme_registry.h"
}

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace stgui {

void slider_level(st_app *a, const char *label, int display)
{
    st_doc *d = &a->doc;
    /* The editing level goes above the top into the HD levels when the
     * interest box allows them (editor.h, "HD levels"). */
    int top = display ? (int)d->h.map.top : (int)st_doc_level_limit(d);
    int v = display ? (int)d->display_level : (int)st_doc_sculpt_level(d);
    int lo = display ? (int)d->edit_level : 0;
    bool off = display && st_doc_display_adaptive(d);
    if (off) ImGui::BeginDisabled();
    if (ImGui::SliderInt(label, &v, lo, top) && a->op == ST_OP_NONE) {
        if (display) st_doc_set_display_level(d, (unsigned)v);
        else st_doc_set_edit_level(d, (unsigned)v);
        st_app_sync(a);
    }
    if (off) ImGui::EndDisabled();
}

void action_button(st_app *a, int id, const char *label)
{
    bool on = st_action_enabled(&st_actions[id], a) != 0;
    if (!on) ImGui::BeginDisabled();
    if (ImGui::Button(label)) g.pending_action = id;
    if (!g.probe_dir.empty()) probe_item(probe_name("panel:", label));
    if (!on) ImGui::EndDisabled();
}

void box_section(st_app *a)
{
    st_doc *d = &a->doc;
    bool on = d->box_on != 0;
    if (ImGui::Checkbox("interest box", &on)) g.pending_action = ST_ACT_BOX_TOGGLE;
    probe_item("panel:interest_box");
    if (!d->box_on) return;
    st_adapt_params b = d->box;
    double c[3], s[3];
    for (int k = 0; k < 3; k++) { c[k] = 0.5 * (b.box_lo[k] + b.box_hi[k]); s[k] = b.box_hi[k] - b.box_lo[k]; }
    float speed = 0.005f * (float)a->cc.radius;
    bool changed = ImGui::DragScalarN("centre", ImGuiDataType_Double, c, 3, speed, nullptr, nullptr, "%.3f");
    bool active = ImGui::IsItemActive();
    double smin = 1e-4 * a->cc.radius;
    changed |= ImGui::DragScalarN("size", ImGuiDataType_Double, s, 3, speed, &smin, nullptr, "%.3f");
    probe_item("panel:size");
    active |= ImGui::IsItemActive();
    int base = (int)b.base_level, mx = (int)b.max_level, top = (int)d->h.map.top + 3;
    if (g.box_pending) { base = (int)g.box_next.base_level; mx = (int)g.box_next.max_level; }
    /* The maximum level stops where the memory budget does (the display's
     * estimate, as st_doc_set_box checks it), asked again only when the
     * box or the model changed. */
    if (g.box_allowed_rev != d->revision + 1 || memcmp(&g.box_allowed_for, &b, sizeof b)) {
        g.box_allowed_for = b;
        g.box_allowed_rev = d->revision + 1;
        g.box_allowed = st_doc_box_max_level_allowed(d, &b);
    }
    int allowed = std::max((int)g.box_allowed, mx);
    top = std::max(top, allowed); /* HD levels: as high as the budget allows */
    bool lv = ImGui::SliderInt("base level", &base, 0, top);
    lv |= ImGui::SliderInt("max level", &mx, 0, std::min(top, allowed));
    if (allowed < top && ImGui::IsItemHovered())
        ImGui::SetTooltip("levels above %d would go over the memory budget (--mem-budget)", allowed);
    /* A drag of the fields is one box operation, as a handle drag. */
    if (active && !g.box_dragging) { st_doc_box_begin(d); g.box_dragging = 1; }
    if ((changed || lv) && a->op == ST_OP_NONE) {
        for (int k = 0; k < 3; k++) { b.box_lo[k] = c[k] - 0.5 * s[k]; b.box_hi[k] = c[k] + 0.5 * s[k]; }
        if (base > mx) { if (lv && base != (int)d->box.base_level) mx = base; else base = mx; }
        b.base_level = (unsigned)base;
        b.max_level = (unsigned)mx;
        if (lv) {
            /* A level change can take seconds: the frame that shows the
             * slider's new value is presented first, and the display is
             * computed before the next one (st_gui_run_pending). */
            g.box_next = b;
            g.box_pending = true;
        } else {
            st_error err;
            if (st_doc_set_box(d, &b, 1, &err)) st_app_message(a, 1, "cannot change the box: %s", err.msg);
            st_app_sync(a);
        }
    }
    if (!active && g.box_dragging) { st_doc_box_end(d); g.box_dragging = 0; st_app_sync(a); }
}

/* A collapsible section of the panel, open or closed as the preferences
 * say (open by default); a click that changes it changes them. */
bool section(const char *name, bool open_by_default = true)
{
    bool was = st_prefs_section_open(name, open_by_default ? 1 : 0) != 0;
    ImGui::SetNextItemOpen(was, ImGuiCond_Once);
    bool open = ImGui::CollapsingHeader(name);
    if (!g.probe_dir.empty()) probe_item(probe_name("panel:section:", name));
    if (open != was) st_prefs_set_section_open(name, open);
    return open;
}

/* The panel's width: the preference (in unscaled units), within
 * [200, 60 % of the window] scaled. */
float panel_width(void)
{
    float lo = 200 * g.scale, hi = std::max(lo, ImGui::GetIO().DisplaySize.x * 0.6f);
    return std::min(hi, std::max(lo, g.panel_w));
}

/* The Mask section: the mask brush and the whole-level operations
 * (ui/doc/editor_mask.c), as actions so that keys, menus and this agree. */
void mask_section(st_app *a)
{
    bool on = a->mask_brush != 0;
    if (ImGui::Checkbox("mask brush (Ctrl+stroke erases)", &on)) g.pending_action = ST_ACT_MASK_BRUSH;
    action_button(a, ST_ACT_MASK_CLEAR, "Clear");
    ImGui::SameLine();
    action_button(a, ST_ACT_MASK_INVERT, "Invert");
    ImGui::SameLine();
    action_button(a, ST_ACT_MASK_GROW, "Grow");
    ImGui::SameLine();
    action_button(a, ST_ACT_MASK_SHRINK, "Shrink");
    action_button(a, ST_ACT_MASK_SMOOTH, "Smooth");
    ImGui::SameLine();
    action_button(a, ST_ACT_MASK_CAVITY, "Mask cavities");
}

/* The Layers section (ui/doc/editor_layers.c): the stack top first; a click
 * makes a layer active (and its level the editing level); visibility,
 * strength (one undo step when the slider is released) and the active
 * layer's name. */
void layers_section(st_app *a)
{
    st_doc *d = &a->doc;
    st_layers *ls = &d->layers;
    static float strength[ST_LAYER_MAX];
    static char name[ST_LAYER_NAME];
    static int name_of = -2;
    st_error err;
    if (ImGui::Selectable("(none: the level's own details)", ls->active < 0)) st_doc_layer_set_active(d, -1, &err);
    for (int k = (int)ls->n - 1; k >= 0; k--) {
        st_layer *y = &ls->v[k];
        ImGui::PushID(k);
        bool vis = !y->hidden;
        if (ImGui::Checkbox("##vis", &vis)) {
            if (st_doc_layer_set_hidden(d, k, !vis, &err)) st_app_message(a, 1, "%s", err.msg);
            st_app_sync(a);
        }
        ImGui::SameLine();
        char label[ST_LAYER_NAME + 32];
        snprintf(label, sizeof label, "%s  (%slevel %u)", y->name, y->level > d->h.map.top ? "HD " : "", y->level);
        if (ImGui::Selectable(label, ls->active == k, 0, ImVec2(120 * g.scale, 0))) {
            st_doc_layer_set_active(d, k, &err);
            st_app_sync(a);
        }
        ImGui::SameLine();
        if (!ImGui::IsAnyItemActive() || !strength[k]) strength[k] = (float)y->strength;
        ImGui::SetNextItemWidth(80 * g.scale);
        ImGui::SliderFloat("##s", &strength[k], 0.0f, (float)ST_LAYER_STRENGTH_MAX, "%.2f");
        if (ImGui::IsItemDeactivatedAfterEdit()) {
            if (st_doc_layer_set_strength(d, k, strength[k], &err)) st_app_message(a, 1, "%s", err.msg);
            st_app_sync(a);
        }
        ImGui::PopID();
    }
    action_button(a, ST_ACT_LAYER_ADD, "New");
    ImGui::SameLine();
    action_button(a, ST_ACT_LAYER_UP, "Up");
    ImGui::SameLine();
    action_button(a, ST_ACT_LAYER_DOWN, "Down");
    ImGui::SameLine();
    action_button(a, ST_ACT_LAYER_MERGE, "Merge");
    ImGui::SameLine();
    action_button(a, ST_ACT_LAYER_DELETE, "Delete");
    int k = ls->active;
    if (k >= 0 && (uint32_t)k < ls->n) {
        if (name_of != k || !ImGui::IsAnyItemActive()) {
            snprintf(name, sizeof name, "%s", ls->v[k].name);
            name_of = k;
        }
        ImGui::InputText("name", name, sizeof name);
        if (ImGui::IsItemDeactivatedAfterEdit() && strcmp(name, ls->v[k].name)) {
            if (st_doc_layer_rename(d, k, name, &err)) st_app_message(a, 1, "%s", err.msg);
        }
    }
}

/* The Filter section of a progressive model (ui/doc/editor_filter.c): a gain
 * per band of details, level 1 (coarsest) to the top, and Apply, which
 * scales the details and re-synthesises as one undo step; the gains then
 * go back to 1, since the details now carry the change. */
void filter_section(st_app *a)
{
    st_doc *d = &a->doc;
    static float gains[ST_MAX_LEVELS];
    static unsigned shown_top = ~0u;
    unsigned top = d->h.map.top;
    if (shown_top != top) {
        for (float &x : gains) x = 1.0f;
        shown_top = top;
    }
    /* Presets first (what most users want), Apply and Reset next to them,
     * the per-level gains below for whoever wants them. */
    for (int p = 0; p < ST_FILTER_NPRESETS; p++) {
        if (p % 2) ImGui::SameLine();
        char label[48];
        snprintf(label, sizeof label, "%s", st_filter_preset_name(p));
        if (ImGui::Button(label)) {
            double gd[ST_MAX_LEVELS];
            st_filter_preset_gains(p, top, gd);
            for (unsigned k = 0; k < top; k++) gains[k] = (float)gd[k];
        }
        if (!g.probe_dir.empty()) probe_item(probe_name("panel:filter:", label));
    }
    bool any = false;
    for (unsigned l = 1; l <= top; l++) any |= gains[l - 1] != 1.0f;
    if (!any) ImGui::BeginDisabled();
    bool apply = ImGui::Button("Apply");
    if (!g.probe_dir.empty()) probe_item("panel:filter:apply");
    ImGui::SameLine();
    bool reset = ImGui::Button("Reset");
    if (!any) ImGui::EndDisabled();
    if (ImGui::TreeNode("gains per level")) {
        ImGui::TextWrapped("details of each level: 0 removes them (smoother), 1 keeps them, 2 doubles them");
        for (unsigned l = 1; l <= top; l++) {
            char label[32];
            snprintf(label, sizeof label, "level %u", l);
            ImGui::SliderFloat(label, &gains[l - 1], 0.0f, 2.0f, "%.2f");
            if (!g.probe_dir.empty()) probe_item(probe_name("panel:filter:", label));
        }
        ImGui::TreePop();
    }
    if (apply && a->op == ST_OP_NONE) {
        double gd[ST_MAX_LEVELS];
        for (unsigned k = 0; k < top; k++) gd[k] = gains[k];
        if (!st_app_filter(a, gd, top)) reset = true;
    }
    if (reset)
        for (float &x : gains) x = 1.0f;
}

void side_panel(st_app *a)
{
    ImGuiIO &io = ImGui::GetIO();
    float w = panel_width();
    /* Its width follows a drag of the left edge (and is remembered); the
     * height fits the content (a 0 size axis is fitted each frame).  The
     * corner grips are not drawn: only the edge resizes. */
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - w, menu_height), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(w, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSizeConstraints(ImVec2(200 * g.scale, 0), ImVec2(std::max(200 * g.scale, io.DisplaySize.x * 0.6f), io.DisplaySize.y - menu_height));
    ImGui::PushStyleColor(ImGuiCol_ResizeGrip, ImVec4(0, 0, 0, 0));
    ImGui::PushStyleColor(ImGuiCol_ResizeGripHovered, ImVec4(0, 0, 0, 0));
    ImGui::PushStyleColor(ImGuiCol_ResizeGripActive, ImVec4(0, 0, 0, 0));
    ImGui::Begin("Strata", nullptr, ImGuiWindowFlags_NoMove);
    ImGui::PopStyleColor(3);
    probe_rect_at("window:panel", ImGui::GetWindowPos(),
                  ImVec2(ImGui::GetWindowPos().x + ImGui::GetWindowWidth(), ImGui::GetWindowPos().y + ImGui::GetWindowHeight()));
    if (std::fabs(ImGui::GetWindowWidth() - w) >= 1) {
        g.panel_w = ImGui::GetWindowWidth();
        st_prefs_set_panel_width(g.panel_w / g.scale);
    }
    st_doc *d = &a->doc;
    ImGui::PushItemWidth(150 * g.scale);
    if (!d->loaded) {
        ImGui::TextUnformatted("No model: File > Open, or drop a file");
    } else {
        uint64_t faces = 0, verts = 0;
        st_doc_display_counts(d, &faces, &verts);
        ImGui::Text("%s  (%s)", st_path_base(d->path), d->scheme ? d->scheme->name : "?");
        if (section("Levels")) {
            slider_level(a, "editing", 0);
            slider_level(a, "displayed", 1);
            ImGui::Text("%llu faces, %llu vertices", (unsigned long long)faces, (unsigned long long)verts);
            ImGui::Text("editing level: %u vertices", a->r.has_cage ? a->r.cage.nverts : 0);
            action_button(a, ST_ACT_ADD_LEVEL, "Add level");
            ImGui::SameLine();
            action_button(a, ST_ACT_DELETE_FINEST, "Delete finest");
            ImGui::SameLine();
            action_button(a, ST_ACT_DELETE_COARSEST, "Rebase");
        }
        if (section("Tool")) {
            /* Three tools a row (clay strips, the longest name, in the middle column). */
            static const int tools[] = { ST_ACT_TOOL_SELECT, ST_ACT_BRUSH_GRAB,    ST_ACT_BRUSH_DRAW,
                                         ST_ACT_BRUSH_SMOOTH, ST_ACT_BRUSH_FLATTEN, ST_ACT_BRUSH_CREASE,
                                         ST_ACT_BRUSH_PINCH,  ST_ACT_BRUSH_INFLATE, ST_ACT_BRUSH_LAYER,
                                         ST_ACT_BRUSH_RELAX,  ST_ACT_BRUSH_CLAY_STRIPS };
            static const int brush_of[] = { ST_TOOL_SELECT, ST_BRUSH_GRAB, ST_BRUSH_DRAW, ST_BRUSH_SMOOTH,
                                            ST_BRUSH_FLATTEN, ST_BRUSH_CREASE, ST_BRUSH_PINCH, ST_BRUSH_INFLATE,
                                            ST_BRUSH_LAYER, ST_BRUSH_RELAX, ST_BRUSH_CLAY_STRIPS };
            const int ntools = (int)(sizeof tools / sizeof tools[0]);
            for (int i = 0; i < ntools; i++) {
                if (i % 3) ImGui::SameLine((float)(i % 3) * 88 * g.scale);
                const char *name = brush_of[i] == ST_TOOL_SELECT ? "select" : st_brush_name(brush_of[i]);
                if (ImGui::RadioButton(name, st_action_checked(&st_actions[tools[i]], a) > 0)) g.pending_action = tools[i];
                if (!g.probe_dir.empty()) probe_item(probe_name("panel:", name));
            }
            float r = (float)d->brush.radius, s = (float)d->brush.strength;
            float rmax = (float)a->cc.radius;
            /* At a coarse level a dab takes in at least the faces under the
             * cursor (st_doc_brush_reach): the slider says so when that is
             * more (in its text, so that the panel's rows stay put). */
            double reach = a->tool != ST_TOOL_SELECT && d->loaded ? st_doc_brush_reach(d) : d->brush.radius;
            char rfmt[48] = "%.4g";
            if (reach > d->brush.radius) snprintf(rfmt, sizeof rfmt, "%%.4g (reach %.3g)", reach);
            if (ImGui::SliderFloat("radius", &r, 0.002f * rmax, rmax, rfmt, ImGuiSliderFlags_Logarithmic)) d->brush.radius = r;
            probe_item("panel:radius");
            if (ImGui::SliderFloat("strength", &s, 0.02f, 1.0f, "%.2f")) d->brush.strength = s;
            /* Symmetry in the model's axes (brush.c). */
            bool mx = d->brush.mirror_x != 0, my = d->brush.mirror_y != 0, mz = d->brush.mirror_z != 0;
            if (ImGui::Checkbox("X", &mx)) d->brush.mirror_x = mx;
            ImGui::SameLine();
            if (ImGui::Checkbox("Y", &my)) d->brush.mirror_y = my;
            ImGui::SameLine();
            if (ImGui::Checkbox("Z mirror", &mz)) d->brush.mirror_z = mz;
            ImGui::SameLine();
            ImGui::Text(" selected %u", d->nsel);
            if (ImGui::TreeNode("falloff, spacing, stabiliser")) {
                if (ImGui::BeginCombo("falloff", st_falloff_name(d->brush.falloff))) {
                    for (int k = 0; k < ST_FALLOFF_COUNT; k++)
                        if (ImGui::Selectable(st_falloff_name(k), d->brush.falloff == k)) d->brush.falloff = k;
                    ImGui::EndCombo();
                }
                float sp = (float)d->brush.spacing;
                if (ImGui::SliderFloat("spacing", &sp, 0.0f, 1.0f, "%.2f radius")) d->brush.spacing = sp;
                /* Per brush (brush.c: autosmooth); the stroke's fade (in and out),
                 * spacing attenuation and hold for every brush. */
                float as = (float)d->brush.autosmooth, fade = (float)d->brush.fade;
                if (ImGui::SliderFloat("auto-smooth", &as, 0.0f, 1.0f, "%.2f")) d->brush.autosmooth = as;
                if (ImGui::SliderFloat("fade", &fade, 0.0f, 4.0f, "%.2f radius each end")) d->brush.fade = fade;
                bool atten = d->brush.space_atten != 0, hold = d->brush.hold != 0;
                if (ImGui::Checkbox("strength for spacing", &atten)) d->brush.space_atten = atten;
                ImGui::SameLine();
                if (ImGui::Checkbox("hold the surface", &hold)) d->brush.hold = hold;
                bool lazy = d->brush.stabilize != 0;
                if (ImGui::Checkbox("stabiliser", &lazy)) d->brush.stabilize = lazy;
                ImGui::SameLine();
                bool front = d->brush.front_only != 0;
                if (ImGui::Checkbox("front faces only", &front)) d->brush.front_only = front;
                ImGui::TreePop();
            }
        }
        if (section("Interest box")) box_section(a);
        if (section("Display")) {
            int sh = a->shading;
            if (ImGui::RadioButton("smooth", sh == ST_SHADE_SMOOTH)) a->shading = ST_SHADE_SMOOTH;
            ImGui::SameLine();
            if (ImGui::RadioButton("flat", sh == ST_SHADE_FLAT)) a->shading = ST_SHADE_FLAT;
            ImGui::SameLine();
            bool cage = a->cage != 0, wire = a->wire != 0;
            if (ImGui::Checkbox("cage", &cage)) g.pending_action = ST_ACT_CAGE;
            ImGui::SameLine();
            if (ImGui::Checkbox("wire", &wire)) a->wire = wire;
        }
        /* Last, so that the sections above keep their places. */
        if (section("Mask", false)) mask_section(a);
        if (section("Layers", false)) layers_section(a);
        if (d->scheme == st_scheme_find("progressive") && section("Filter", false)) filter_section(a);
    }
    if (section("Timings")) {
        char t1[32], t2[32], t3[32];
        ImGui::Text("frame %s", st_app_fmt_ms(a, a->frame_ms, t1, sizeof t1));
        ImGui::Text("update: geometry %s, buffers %s", st_app_fmt_ms(a, d->loaded ? d->last_update_ms : 0, t2, sizeof t2),
                    st_app_fmt_ms(a, a->update_ms, t3, sizeof t3));
        ImGui::Text("undo %u/%u   %s", d->undo_pos, d->nundo, a->cc.cam.ortho ? "ortho" : "persp");
    }
    ImGui::PopItemWidth();
    ImGui::End();
}

}  // namespace stgui
