/* igea version */
#include <string.h>

#include "cli.h"

int cmd_version(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            printf("usage: igea version\n\nPrints the version of the igea driver and of "
                   "the library it runs on.\n");
            return CLI_OK;
        }
        cli_error("version: unexpected argument '%s'", argv[i]);
        return CLI_USAGE;
    }
    printf("igea %s (library %s, IGEA_VERSION_NUMBER %d)\n", IGEA_VERSION_STRING,
           igea_version(), igea_version_number());
    return CLI_OK;
}
