/* The window's windows besides the file dialog and the side panel (Dear
 * ImGui): the unsaved-changes question on quit, the scheme question,
 * About, Preferences, Bake maps, the key list and the progress window of
 * a job with its Cancel.  Widgets named for tests/cli/cli_gui_xdotool.sh
 * (STRATA_GUI_PROBE). */
#include "gui_internal.h"

extern "C" {
#include "actions.h"
#include "prefs.h"
}

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <unistd.h>

namespace stgui {

/* Quitting with unsaved changes (st_app_request_quit): S, D and any other
 * key answer it too (actions.c). */
void quit_window(st_app *a)
{
    if (!a->quit_asking) return;
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("Quit Strata?", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse);
    probe_item("quit:window");
    ImGui::Text("Save the changes to %s before quitting?", a->untitled ? "the untitled model" : st_path_base(a->doc.path));
    ImGui::TextDisabled("Without saving, the last changes stay only in the recovery file.");
    if (ImGui::Button("Save")) g.pending_action = ST_ACT_QUIT_SAVE;
    probe_item("quit:Save");
    ImGui::SameLine();
    if (ImGui::Button("Don't save")) g.pending_action = ST_ACT_QUIT_DISCARD;
    probe_item("quit:Don't save");
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) g.pending_action = ST_ACT_QUIT_CANCEL;
    probe_item("quit:Cancel");
    ImGui::End();
}

/* The scheme question of K (or the Scheme menu): Y / Enter, K, N still work. */
void scheme_window(st_app *a)
{
    if (!a->pending_scheme) return;
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("Change the scheme?", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::Text("Rebuild the hierarchy with %s?", a->pending_scheme);
    ImGui::TextDisabled("The details of the current levels are lost.");
    char b[96];
    snprintf(b, sizeof b, "Rebuild with %s", a->pending_scheme);
    if (ImGui::Button(b)) g.pending_action = ST_ACT_SCHEME_CONFIRM;
    ImGui::SameLine();
    if (ImGui::Button("Next scheme")) g.pending_action = ST_ACT_SCHEME_NEXT;
    ImGui::SameLine();
    if (ImGui::Button("Keep")) g.pending_action = ST_ACT_SCHEME_KEEP;
    ImGui::End();
}

void about_window(void)
{
    if (!g.about) return;
    ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x * 0.5f, ImGui::GetIO().DisplaySize.y * 0.4f), ImGuiCond_Appearing,
                            ImVec2(0.5f, 0.5f));
    if (ImGui::Begin("About Strata", &g.about, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse)) {
        ImGui::Text("Strata %s", STRATA_VERSION);
        ImGui::TextDisabled("interactive multiresolution subdivision modelling");
        ImGui::Separator();
        ImGui::Text("Dear ImGui %s", IMGUI_VERSION);
        ImGui::Text("GLFW %s", glfwGetVersionString());
    }
    ImGui::End();
}

/* Edit > Preferences: what the user sets by hand (prefs.h); the rest
 * (window size, panel layout, brush defaults, recent files) is kept as the
 * window is used and saved at exit.  "Save now" writes the file at once. */
void prefs_window(st_app *a)
{
    if (!g.prefs) return;
    ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x * 0.5f, ImGui::GetIO().DisplaySize.y * 0.4f), ImGuiCond_Appearing,
                            ImVec2(0.5f, 0.5f));
    if (ImGui::Begin("Preferences", &g.prefs, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse)) {
        char path[4096];
        ImGui::Text("kept in %s", st_prefs_path(path, sizeof path) ? "(no $XDG_CONFIG_HOME or $HOME: not kept)" : path);
        ImGui::Separator();
        float s = st_prefs_ui_scale();
        if (ImGui::SliderFloat("UI scale", &s, 0.0f, 4.0f, s > 0 ? "%.2f" : "auto (monitor)")) st_prefs_set_ui_scale(s);
        probe_item("prefs:ui_scale");
        ImGui::TextDisabled("now %.2f; a new scale applies at the next start (--ui-scale overrides it)", g.scale);
        const char *const *recent = st_prefs_recent();
        int nrecent = 0;
        while (recent[nrecent]) nrecent++;
        ImGui::Text("%d recent file%s", nrecent, nrecent == 1 ? "" : "s");
        ImGui::SameLine();
        if (ImGui::Button("Clear")) st_prefs_clear_recent();
        probe_item("prefs:clear_recent");
        const char *tool = st_prefs_brush_tool();
        ImGui::Text("brush at start: %s, radius %.3g of the model, strength %.2g", tool[0] ? tool : "(default)",
                    st_prefs_brush_radius(), st_prefs_brush_strength());
        ImGui::TextDisabled("(the brush in use when the window closes)");
        if (ImGui::Button("Save now")) {
            if (st_prefs_save()) st_app_message(a, 1, "preferences not saved (see the terminal)");
            else st_app_message(a, 0, "preferences saved");
        }
        probe_item("prefs:save");
    }
    ImGui::End();
}

/* A path the user typed, relative to the working directory, made absolute
 * (the job's messages and the view read it later). */
void absolute_path(char *p, size_t n)
{
    if (!p[0] || p[0] == '/') return;
    char cwd[4096];
    if (!getcwd(cwd, sizeof cwd)) return;
    std::string full = std::string(cwd) + "/" + p;
    if (full.size() < n) memcpy(p, full.c_str(), full.size() + 1);
}

/* Bake > Bake maps...: strata bake's options (formats/bake_run.h); Bake
 * runs the job (progress, Esc or Cancel) after this frame. */
void bake_window(st_app *a)
{
    if (!g.bake) return;
    if (!a->doc.loaded) { g.bake = false; return; }
    st_app_bake *b = &a->bake;
    st_app_bake_defaults(a);
    int top = (int)a->doc.h.map.top;
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.4f, io.DisplaySize.y * 0.45f), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (!ImGui::Begin("Bake maps", &g.bake, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse)) { ImGui::End(); return; }
    ImGui::TextDisabled("level %d's surface onto level %d's UVs (strata bake)", b->level, b->base);
    float w = 260 * g.scale;
    ImGui::SetNextItemWidth(w);
    ImGui::SliderInt("Base level (gets the maps)", &b->base, 0, top);
    probe_item("bake:base");
    if (b->level < b->base) b->level = b->base;
    ImGui::SetNextItemWidth(w);
    ImGui::SliderInt("Detail level", &b->level, b->base, top);
    probe_item("bake:level");
    static const int sizes[] = { 256, 512, 1024, 2048, 4096, 8192 };
    static const char *const size_names[] = { "256", "512", "1024", "2048", "4096", "8192" };
    int si = 2;
    for (int i = 0; i < 6; i++) if (sizes[i] == b->size) si = i;
    ImGui::SetNextItemWidth(w);
    if (ImGui::Combo("Resolution", &si, size_names, 6)) b->size = sizes[si];
    probe_item("bake:size");
    ImGui::Separator();
    bool on = b->want_normal != 0;
    if (ImGui::Checkbox("Normal map", &on)) b->want_normal = on;
    probe_item("bake:normal");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(w + 40 * g.scale);
    ImGui::InputText("##normal_path", b->normal, sizeof b->normal, ImGuiInputTextFlags_AutoSelectAll);
    probe_item("bake:normal_path");
    ImGui::RadioButton("Tangent space", &b->space, ST_BAKE_TANGENT);
    ImGui::SameLine();
    ImGui::RadioButton("Object space", &b->space, ST_BAKE_OBJECT);
    ImGui::SameLine();
    on = b->bits16 != 0;
    if (ImGui::Checkbox("16-bit", &on)) b->bits16 = on;
    on = b->want_disp != 0;
    if (ImGui::Checkbox("Displacement", &on)) b->want_disp = on;
    probe_item("bake:disp");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(w + 40 * g.scale);
    ImGui::InputText("##disp_path", b->disp, sizeof b->disp, ImGuiInputTextFlags_AutoSelectAll);
    ImGui::TextDisabled(".exr (float) or .png (16-bit, scale in NAME.json)");
    on = b->vector != 0;
    if (ImGui::Checkbox("Vector displacement", &on)) b->vector = on;
    ImGui::Separator();
    static const char *const udims[] = { "auto", "off (one map)", "on (one map per tile)" };
    int ui = b->udim < 0 ? 0 : b->udim == 0 ? 1 : 2;
    ImGui::SetNextItemWidth(w);
    if (ImGui::Combo("UDIM tiles", &ui, udims, 3)) b->udim = ui == 0 ? -1 : ui == 1 ? 0 : 1;
    probe_item("bake:udim");
    ImGui::SetNextItemWidth(w);
    ImGui::SliderInt("Padding (texels)", &b->padding, 0, 64);
    bool has_uv = st_hier_has_uv(&a->doc.h, (unsigned)b->base) != 0;
    on = b->auto_uv != 0 || !has_uv;
    if (!has_uv) ImGui::BeginDisabled();
    if (ImGui::Checkbox("Auto UVs (an atlas of charts)", &on)) b->auto_uv = on;
    if (!has_uv) { ImGui::EndDisabled(); ImGui::SameLine(); ImGui::TextDisabled("level %d has no UVs", b->base); }
    probe_item("bake:auto_uv");
    if (!g.bake_error.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.4f, 1));
        ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + 520 * g.scale);
        ImGui::TextWrapped("%s", g.bake_error.c_str());
        ImGui::PopTextWrapPos();
        ImGui::PopStyleColor();
    }
    if (ImGui::Button("Bake", ImVec2(90 * g.scale, 0))) g.bake_go = true;
    probe_item("bake:run");
    ImGui::SameLine();
    if (ImGui::Button("Close", ImVec2(90 * g.scale, 0))) g.bake = false;
    probe_item("bake:close");
    ImGui::End();
}

/* Help > Key bindings (F1): the same rows as the HUD's F1 list and the
 * README's table (st_help_rows). */
void keys_window(st_app *a)
{
    if (!a->help) return;
    static st_help_row rows[ST_HELP_MAX_ROWS];
    unsigned n = st_help_rows(rows, ST_HELP_MAX_ROWS);
    if (n > ST_HELP_MAX_ROWS) n = ST_HELP_MAX_ROWS;
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(20 * g.scale, menu_height + 10 * g.scale), ImGuiCond_Appearing);
    ImGui::SetNextWindowSize(ImVec2(std::min(760 * g.scale, io.DisplaySize.x - 40 * g.scale), io.DisplaySize.y * 0.8f),
                             ImGuiCond_Appearing);
    bool open = true;
    if (ImGui::Begin("Key bindings (F1)", &open) && ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_Resizable)) {
        ImGui::TableSetupColumn("keys", ImGuiTableColumnFlags_WidthFixed, 300 * g.scale);
        ImGui::TableSetupColumn("what", ImGuiTableColumnFlags_WidthStretch);
        for (unsigned i = 0; i < n; i++) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            if (rows[i].heading) { ImGui::TextColored(ImVec4(1, 0.8f, 0.4f, 1), "%s", rows[i].heading); continue; }
            ImGui::TextUnformatted(rows[i].keys);
            ImGui::TableSetColumnIndex(1);
            ImGui::TextWrapped("%s", rows[i].what);
        }
        ImGui::EndTable();
    }
    ImGui::End();
    if (!open) a->help = 0;
}

/* What the window is doing on its worker thread (jobs.c): the stage and
 * how far it is (the fraction the editor reports, else its steps, "step 3
 * of 6").  Jobs (opening, adding a level, a scheme change, saving,
 * rebuilding the levels) have a Cancel button, as Esc: the worker stops at
 * its next progress report and the model stays as it was (editor.h,
 * st_doc_*_progress). */
void progress_window(st_app *a)
{
    if (!a->working[0]) return;
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(420 * g.scale, 0));
    ImGui::Begin("Working", nullptr, ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove);
    ImGui::TextWrapped("%s", a->working);
    unsigned step = 0, steps = 0;
    const char *s = strstr(a->working, "step ");
    if (s) sscanf(s, "step %u of %u", &step, &steps);
    char over[32];
    if (steps) snprintf(over, sizeof over, "step %u of %u", step, steps);
    else snprintf(over, sizeof over, "working...");
    double fraction = st_app_job_fraction();
    if (fraction >= 0) snprintf(over, sizeof over, "%.0f %%", 100 * fraction);
    ImGui::ProgressBar(fraction >= 0 ? (float)fraction : steps ? (float)step / (float)steps : 0.0f, ImVec2(-1, 0), over);
    if (st_app_job_cancellable()) {
        bool asked = st_app_job_cancelling();
        if (asked) ImGui::BeginDisabled();
        if (ImGui::Button(asked ? "Cancelling..." : "Cancel", ImVec2(100 * g.scale, 0))) st_app_cancel_job();
        probe_item("progress:Cancel");
        if (asked) ImGui::EndDisabled();
    }
    ImGui::End();
}

}  // namespace stgui
