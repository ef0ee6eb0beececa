#ifndef ST_CLI_H
#define ST_CLI_H

int st_cmd_info(int argc, char **argv);
int st_cmd_subdivide(int argc, char **argv);
int st_cmd_adapt(int argc, char **argv);
int st_cmd_render(int argc, char **argv);
/* app/cmd_convert.c: `strata convert IN OUT`. */
int st_cmd_convert(int argc, char **argv);
int st_cmd_filter(int argc, char **argv);
/* app/cmd_window.c: `strata [options] [FILE]` opens the modeller. */
int st_cmd_window(int argc, char **argv);
/* app/cmd_rebuild.c: a dense mesh into a hierarchy (unsubdivide / progressive). */
int st_cmd_rebuild(int argc, char **argv);
/* app/cmd_bake.c: normal and displacement maps of a level onto a coarser one. */
int st_cmd_bake(int argc, char **argv);
/* app/cmd_deform.c: a scripted edit (a Gaussian bump at one level). */
int st_cmd_deform(int argc, char **argv);

#endif
