/* resurf: command dispatch, --help and --version. */
#include <signal.h>
#include <string.h>

#include "cli.h"

static const cli_command commands[] = {
    {"info", "print counts, topology, bounds and attributes of a mesh", cmd_info},
    {"convert", "convert a mesh between OBJ, PLY, OFF and STL", cmd_convert},
    {"restore", "move the vertices of a processed mesh back onto the original's smooth surface", cmd_restore},
    {"smooth", "smooth a mesh (Laplacian, Taubin, cotangent Taubin, bilaplacian)", cmd_smooth},
    {"compare", "measure the distance between two meshes' surfaces and triangle quality", cmd_compare},
    {"simplify", "simplify a mesh by edge collapses restored onto its smooth surface (levels of detail)", cmd_simplify},
    {"lod", "levels of detail of a glTF scene (or mesh) as MSFT_lod, files or side by side, Draco-compressed", cmd_lod},
    {"preview", "draw every level of detail of a scene with its error into a PNG sheet", cmd_preview},
};

static void print_help(FILE *f)
{
    fprintf(f, "usage: resurf COMMAND [OPTIONS] ...\n\n"
               "Levels of detail whose vertices stay on the smooth surface the original mesh approximates.\n\n"
               "commands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        fprintf(f, "  %-9s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n'resurf COMMAND --help' describes a command.\n"
               "Exit status: 0 success, 1 the work failed, 2 usage error, 130/143 interrupted by SIGINT/SIGTERM.\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        print_help(stderr);
        return CLI_USAGE;
    }
    const char *name = argv[1];
    if (!strcmp(name, "--help") || !strcmp(name, "-h") || !strcmp(name, "help")) {
        print_help(stdout);
        return CLI_OK;
    }
    if (!strcmp(name, "--version") || !strcmp(name, "-V")) {
        printf("resurf %s\n", resurf_version());
        return CLI_OK;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        if (!strcmp(name, commands[i].name)) {
            cli_install_signal_handlers();
            int rc = commands[i].run(argc - 1, argv + 1);
            int signo = cli_interrupted();
            if (signo) {
                /* The library cancelled at its next progress report and removed its temporary file; any output
                 * either was complete before the signal or was not written. */
                fprintf(stderr, "resurf: interrupted by %s\n", signo == SIGINT ? "SIGINT" : "SIGTERM");
                return 128 + signo;
            }
            return rc;
        }
    fprintf(stderr, "resurf: unknown command '%s' (see 'resurf --help')\n", name);
    return CLI_USAGE;
}
