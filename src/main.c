/* main.c: the rodsim command line (frame placeholder). */
#include <stdio.h>
#include <string.h>
#include "fem_cli.h" /* temporary dispatch until the lead adds fem to the table */

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "fem") == 0) return fem_command(argc - 1, argv + 1);
    if (argc > 1 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        printf("usage: rodsim run SCENE | rodsim fem SCENE\n");
        return 0;
    }
    fprintf(stderr, "rodsim: no command given; see rodsim --help\n");
    return 2;
}
