/* strata convert (issue 7): placeholder until the session/interchange work lands. */
#include "cli.h"

#include <stdio.h>

int st_cmd_convert(int argc, char **argv)
{
    (void)argc; (void)argv;
    fprintf(stderr, "strata convert: not built yet\n");
    return 2;
}
