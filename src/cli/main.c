/* igea - command-line driver (see run.c). */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

int main(int argc, char **argv)
{
    int ec = cli_run(argc, argv);
    errno = 0;
    if (fclose(stdout) != 0 && (ec == CLI_OK || ec == CLI_REJECT)) {
        cli_error("writing standard output: %s", errno ? strerror(errno) : "I/O error");
        ec = CLI_IOERR;
    }
    return ec;
}
