/* resurf restore: being written. */
#include "cli.h"

int cmd_restore(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    return cli_fail("restore: not implemented yet");
}
