/* run.c - the driver's dispatch: the command named by argv[1], then the
 * check that standard output really was written. */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

typedef struct {
    const char *name;
    int (*run)(int, char **);
    const char *summary;
} command;

static const command commands[] = {
    {"eqerr", cmd_eqerr, "equivalent-error accuracy assessment of one flight (seed 000)"},
    {"test", cmd_test, "judge saved results: pool flights, or a table of (Xhat, lambda)"},
    {"regress", cmd_regress, "least squares, ridge, PCE, Bayes and empirical-Bayes ridge with diagnostics"},
    {"rls", cmd_rls, "recursive (standard, iterated, polynomial) RLS over a stream of epochs (seed 001)"},
    {"redund", cmd_redund, "redundant sensors: reliability, consistency, fusion, parity FDI (seed 002)"},
    {"stability", cmd_stability, "block 3-sigma (100-s variance) and Allan deviation of a record"},
    {"accel", cmd_accel, "dividing-head accelerometer calibration, single and dual g^2 models (seed 003)"},
    {"envfun", cmd_envfun, "environment-function matrix S of a trajectory and error terms"},
    {"dw", cmd_dw, "telemetry minus tracking: dW at the tracking epochs from raw records"},
    {"simulate", cmd_simulate, "a synthetic flight test with known truth: S, dw, sigma, spec, X files"},
    {"montecarlo", cmd_montecarlo, "size and power of the accuracy test over many simulated flights"},
    {"impact", cmd_impact, "impact point of a free flight, miss per burnout error, budget and CEP"},
    {"triad", cmd_triad, "IMU calibration without a turntable: accelerometer and gyro triads from static attitudes"},
    {"nav", cmd_nav, "INS error propagation: position, velocity, attitude errors from sensor errors"},
    {"version", cmd_version, "print the library and driver version"},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: igea <command> [options]   (inputs are options: --S FILE, --data FILE, ...)\n\n"
               "Inertial guidance error analysis. Commands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n'igea <command> --help' (or 'igea help <command>') explains a command with\n"
               "an example; options are --name VALUE or --name=VALUE, each at most once.\n"
               "Exit status: 0 ok / accepted, 1 an accuracy test rejected, 64 usage,\n"
               "65 bad input data, 66 missing input, 70 numerical failure, 74 I/O error.\n");
}

static int dispatch(int argc, char **argv)
{
    igea_init();
    if (argc < 2) {
        usage(stderr);
        return CLI_USAGE;
    }
    if (!strcmp(argv[1], "help") && argc > 2) { /* igea help CMD = igea CMD --help */
        char help[] = "--help";
        char *args[] = {argv[2], help, NULL};
        for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
            if (!strcmp(argv[2], commands[i].name))
                return commands[i].run(2, args);
        cli_error("help: unknown command '%s' (try 'igea --help')", argv[2]);
        return CLI_USAGE;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return CLI_OK;
    }
    if (!strcmp(argv[1], "--version"))
        return cmd_version(1, argv + 1);
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (!strcmp(argv[1], commands[i].name))
            return commands[i].run(argc - 1, argv + 1);
    cli_error("unknown command '%s' (try 'igea --help')", argv[1]);
    return CLI_USAGE;
}

int cli_run(int argc, char **argv)
{
    clearerr(stdout);
    int ec = dispatch(argc, argv);
    errno = 0;
    if (fflush(stdout) != 0 || ferror(stdout)) {
        int e = errno;
        clearerr(stdout);
        if (ec == CLI_OK || ec == CLI_REJECT) {
            cli_error("writing standard output: %s", e ? strerror(e) : "I/O error");
            ec = CLI_IOERR;
        }
    }
    return ec;
}
