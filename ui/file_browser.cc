/* The window's file dialog (Dear ImGui): Open, Import, Save session as and
 * Export, one dialog listing a folder's sub-folders and the files of the
 * formats the kind reads or writes, a path field completed with the
 * written extension, an overwrite question, and the choice run outside
 * the frame (opening is a job, ui/jobs.c).  Its state is gui_state's
 * dlg_* fields (gui_internal.h); STRATA_GUI_PROBE names its widgets for
 * tests/cli/cli_gui_xdotool.sh. */
#include "gui_internal.h"

extern "C" {
#include "prefs.h"
}

#include <dirent.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace stgui {

bool ends_with_ci(const char *s, const char *ext)
{
    size_t n = strlen(s), m = strlen(ext);
    return n >= m && !strcasecmp(s + n - m, ext);
}

bool wanted_file(int kind, const char *name)
{
    if (kind == ST_DIALOG_OPEN || kind == ST_DIALOG_IMPORT) {
        /* Import: the mesh formats, not sessions. */
        for (const char *e : read_exts)
            if (ends_with_ci(name, e) && (kind == ST_DIALOG_OPEN || strcmp(e, ".strata"))) return true;
        return false;
    }
    if (kind == ST_DIALOG_SAVE_AS) return ends_with_ci(name, ".strata");
    return ends_with_ci(name, export_exts[g.dlg_format]);
}

/* Folders first, then files of the dialog's formats, each by name. */
void list_dir(void)
{
    g.entries.clear();
    DIR *d = opendir(g.cwd.c_str());
    if (!d) { g.dlg_error = "cannot read the folder " + g.cwd + ": " + strerror(errno); return; }
    while (struct dirent *e = readdir(d)) {
        if (e->d_name[0] == '.') continue;   /* hidden files and . / .. (Parent goes up) */
        std::string full = g.cwd + "/" + e->d_name;
        struct stat st;
        if (stat(full.c_str(), &st)) continue;
        bool dir = S_ISDIR(st.st_mode);
        if (!dir && !wanted_file(g.dlg_kind, e->d_name)) continue;
        g.entries.push_back({ e->d_name, dir, (long long)st.st_size });
    }
    closedir(d);
    std::sort(g.entries.begin(), g.entries.end(), [](const file_entry &a, const file_entry &b) {
        if (a.dir != b.dir) return a.dir;
        return a.name < b.name;
    });
}

void set_cwd(const std::string &dir)
{
    char buf[4096];
    g.cwd = realpath(dir.c_str(), buf) ? buf : dir;
    list_dir();
}

std::string dir_of(const char *path)
{
    const char *s = strrchr(path, '/');
    if (!s) return ".";
    if (s == path) return "/";
    return std::string(path, (size_t)(s - path));
}

std::string format_size(long long n)
{
    char b[32];
    if (n >= 1 << 20) snprintf(b, sizeof b, "%.1f MB", n / 1048576.0);
    else if (n >= 1 << 10) snprintf(b, sizeof b, "%.1f KB", n / 1024.0);
    else snprintf(b, sizeof b, "%lld B", n);
    return b;
}

/* The dialog's path completed with the extension its kind writes. */
std::string completed_path(int kind, const char *p)
{
    std::string s = p;
    if (kind == ST_DIALOG_SAVE_AS && !ends_with_ci(p, ".strata")) s += ".strata";
    if (kind == ST_DIALOG_EXPORT) {
        bool known = false;
        for (const char *e : export_exts) known = known || ends_with_ci(p, e);
        if (!known) s += export_exts[g.dlg_format];
    }
    if (!s.empty() && s[0] != '/') s = g.cwd + "/" + s;
    return s;
}

/* Runs the dialog's choice (outside the ImGui frame: opening is a job).
 * A failure keeps the dialog open with the message and the current model. */
void dialog_accept(st_app *a, int kind, const std::string &path)
{
    int rc;
    if (kind == ST_DIALOG_OPEN) {
        rc = st_app_open(a, path.c_str());
    } else if (kind == ST_DIALOG_IMPORT) {
        rc = st_app_import(a, path.c_str());
    } else if (kind == ST_DIALOG_SAVE_AS) {
        rc = st_app_save_session(a, path.c_str(), 0);
        if (!rc && path.size() < sizeof a->doc.path) {
            memcpy(a->doc.path, path.c_str(), path.size() + 1);
            st_app_saved(a);
            a->untitled = 0;
            if (a->quit_after_save) a->quit = 1;
        }
    } else {
        rc = st_app_export(a, path.c_str());
    }
    if (rc) {
        g.dlg_error = a->msg;
        return;
    }
    if (kind != ST_DIALOG_EXPORT && kind != ST_DIALOG_IMPORT) st_prefs_add_recent(path.c_str());   /* imports are not documents */
    g.dlg_open = false;
    g.dlg_error.clear();
}

void open_dialog(st_app *a, int kind, int format)
{
    a->quit_after_save = 0;
    g.dlg_open = true;
    g.dlg_popup = true;
    g.dlg_confirm = false;
    g.dlg_kind = kind;
    g.dlg_format = format;
    g.dlg_error.clear();
    g.path[0] = 0;
    const char *doc = a->doc.loaded ? a->doc.path : "";
    /* The open document's folder, or the working directory: not the
     * folder of the default model shown at start (assets/), which is not
     * the user's. */
    bool own = doc[0] && !a->showing_default;
    std::string start = own ? dir_of(doc) : ".";
    if (kind != ST_DIALOG_OPEN && kind != ST_DIALOG_IMPORT && doc[0]) {
        /* The model's name with the extension of what is written. */
        const char *base = st_path_base(doc);
        const char *dot = strrchr(base, '.');
        int n = dot ? (int)(dot - base) : (int)strlen(base);
        snprintf(g.path, sizeof g.path, "%.*s%s", n, base, kind == ST_DIALOG_SAVE_AS ? ".strata" : export_exts[format]);
    }
    set_cwd(start);
    g.shown = true;
}

void file_dialog(st_app *a)
{
    const char *title = g.dlg_kind == ST_DIALOG_OPEN     ? "Open###filedialog"
                        : g.dlg_kind == ST_DIALOG_IMPORT ? "Import a mesh###filedialog"
                        : g.dlg_kind == ST_DIALOG_SAVE_AS ? "Save session as###filedialog"
                                                          : "Export the displayed mesh###filedialog";
    /* (Again after a job: its frames drew no dialog.) */
    if (g.dlg_popup || !ImGui::IsPopupOpen("###filedialog")) { ImGui::OpenPopup("###filedialog"); g.dlg_popup = false; }
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowSize(ImVec2(560 * g.scale, 420 * g.scale), ImGuiCond_Appearing);
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    bool open = true;
    if (!ImGui::BeginPopupModal(title, &open)) {
        if (!open || g.dlg_open) g.dlg_open = g.dlg_open && open;
        return;
    }
    ImGui::TextUnformatted(g.cwd.c_str());
    if (ImGui::Button("Parent")) set_cwd(dir_of(g.cwd.c_str()));
    ImGui::SameLine();
    if (ImGui::Button("Refresh")) list_dir();
    ImGui::SameLine();
    if (g.dlg_kind == ST_DIALOG_OPEN) ImGui::TextDisabled(".obj .off .ply .gltf .glb .strata");
    else if (g.dlg_kind == ST_DIALOG_IMPORT) ImGui::TextDisabled(".obj .off .ply .gltf .glb (a new untitled document)");
    else if (g.dlg_kind == ST_DIALOG_SAVE_AS) ImGui::TextDisabled(".strata");
    else ImGui::TextDisabled("%s of the displayed %s", export_exts[g.dlg_format], a->doc.box_on ? "adaptive mesh" : "level");
    /* A row of options under the list (the list's top and the path row
     * stay where they were: replays click there). */
    bool options = (g.dlg_kind == ST_DIALOG_EXPORT && g.dlg_format >= 2) || g.dlg_kind == ST_DIALOG_OPEN || g.dlg_kind == ST_DIALOG_IMPORT;
    float footer = ImGui::GetFrameHeightWithSpacing() * (options ? 3 : 2) +
                   (g.dlg_error.empty() ? 0 : ImGui::GetTextLineHeightWithSpacing() * 2);
    ImGui::BeginChild("entries", ImVec2(0, -footer), true);
    std::string go;
    for (const file_entry &e : g.entries) {
        std::string label = e.dir ? "[dir] " + e.name : e.name;
        bool sel = !e.dir && !strcmp(g.path, e.name.c_str());
        if (ImGui::Selectable(label.c_str(), sel, ImGuiSelectableFlags_AllowDoubleClick)) {
            if (e.dir) go = e.name;
            else {
                snprintf(g.path, sizeof g.path, "%s", e.name.c_str());
                g.dlg_confirm = false;
                if (ImGui::IsMouseDoubleClicked(0)) g.dlg_accept = true;
            }
        }
        if (!e.dir) {
            ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 90 * g.scale);
            ImGui::TextDisabled("%s", format_size(e.size).c_str());
        }
    }
    ImGui::EndChild();
    if (!go.empty()) set_cwd(g.cwd + "/" + go);
    /* glTF can carry the last baked normal map (normalTexture, TANGENT);
     * a mesh file cannot.  Opening can refuse non-manifold edges. */
    if (g.dlg_kind == ST_DIALOG_EXPORT && g.dlg_format >= 2) {
        bool can = st_app_can_show_baked(a) != 0, on = can && a->bake.attach;
        if (!can) ImGui::BeginDisabled();
        if (ImGui::Checkbox("Attach the baked normal map", &on)) a->bake.attach = on;
        if (!can) ImGui::EndDisabled();
        probe_item("dialog:attach");
        ImGui::SameLine();
        if (can) ImGui::TextDisabled("(writes level %u with %s)", a->bake.have_base, st_path_base(a->bake.have_map));
        else ImGui::TextDisabled("(Bake > Bake maps... makes one)");
    }
    if (g.dlg_kind == ST_DIALOG_OPEN || g.dlg_kind == ST_DIALOG_IMPORT) {
        bool strict = (a->doc.read_flags & ST_MESH_STRICT) != 0;
        if (ImGui::Checkbox("Refuse non-manifold edges (--strict; else they are split)", &strict))
            a->doc.read_flags = strict ? a->doc.read_flags | ST_MESH_STRICT : a->doc.read_flags & ~ST_MESH_STRICT;
        probe_item("dialog:strict");
    }
    if (!g.dlg_error.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.4f, 1));
        ImGui::TextWrapped("%s", g.dlg_error.c_str());
        ImGui::PopStyleColor();
    }
    ImGui::SetNextItemWidth(-160 * g.scale);
    /* A click in the field selects what it holds, so that a typed path
     * replaces the proposed name. */
    if (ImGui::InputText("##path", g.path, sizeof g.path, ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll))
        g.dlg_accept = true;
    probe_item("dialog:path");
    ImGui::SameLine();
    const char *ok = g.dlg_kind == ST_DIALOG_OPEN      ? "Open"
                     : g.dlg_kind == ST_DIALOG_IMPORT  ? "Import"
                     : g.dlg_kind == ST_DIALOG_SAVE_AS ? "Save"
                                                       : "Export";
    if (ImGui::Button(ok, ImVec2(70 * g.scale, 0)) && g.path[0]) g.dlg_accept = true;
    probe_item("dialog:ok");
    ImGui::SameLine();
    bool cancel = ImGui::Button("Cancel", ImVec2(70 * g.scale, 0));
    probe_item("dialog:cancel");
    if (cancel || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) {
        g.dlg_open = false;
        g.dlg_accept = false;
    }
    if (g.dlg_accept) {
        std::string full = completed_path(g.dlg_kind, g.path);
        struct stat st;
        if (!g.path[0]) g.dlg_accept = false;
        else if (!stat(full.c_str(), &st) && S_ISDIR(st.st_mode)) { set_cwd(full); g.path[0] = 0; g.dlg_accept = false; }
        else if (g.dlg_kind != ST_DIALOG_OPEN && g.dlg_kind != ST_DIALOG_IMPORT && !g.dlg_confirm && !stat(full.c_str(), &st)) {
            g.dlg_confirm = true;   /* asks below; the choice runs on "Overwrite" */
            g.dlg_accept = false;
        }
    }
    if (g.dlg_confirm) {
        ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "%s exists.", g.path);
        ImGui::SameLine();
        if (ImGui::Button("Overwrite")) { g.dlg_accept = true; }
        probe_item("dialog:Overwrite");
        ImGui::SameLine();
        if (ImGui::Button("Keep it")) g.dlg_confirm = false;
    }
    if (!open) a->quit_after_save = 0;   /* closed without saving: no quit */
    if (!g.dlg_open || !open) { g.dlg_open = false; ImGui::CloseCurrentPopup(); }
    ImGui::EndPopup();
}

}  // namespace stgui
