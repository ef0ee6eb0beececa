/* strata [FILE] (issue 6): placeholder until the modeller window lands. */
#include "cli.h"

#include <stdio.h>

int st_cmd_window(int argc, char **argv)
{
    (void)argc; (void)argv;
    fprintf(stderr, "strata: the interactive window is not built yet\n");
    return 2;
}
