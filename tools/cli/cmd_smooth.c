/* resurf smooth: being written. */
#include "cli.h"

int cmd_smooth(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    return cli_fail("smooth: not implemented yet");
}
