#ifndef ST_CLI_H
#define ST_CLI_H

int st_cmd_info(int argc, char **argv);
int st_cmd_subdivide(int argc, char **argv);
int st_cmd_adapt(int argc, char **argv);
int st_cmd_render(int argc, char **argv);

#endif
