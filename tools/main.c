#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/version.h"

static const pc_command pc_commands[] = {
#define PC_COMMAND_ENTRY(name, summary) { #name, summary, cmd_##name },
	PC_COMMANDS(PC_COMMAND_ENTRY)
#undef PC_COMMAND_ENTRY
};

static void usage(FILE *fp)
{
	fprintf(fp, "usage: polarcam COMMAND [OPTIONS]   (polarcam COMMAND --help for details)\n\n"
		    "Simulate and process division-of-focal-plane polarization cameras.\n\n"
		    "commands:\n");
	for (size_t i = 0; i < sizeof pc_commands / sizeof pc_commands[0]; i++)
		fprintf(fp, "  %-10s %s\n", pc_commands[i].name, pc_commands[i].summary);
	fprintf(fp, "\nExit status: 0 success, 1 failure, 2 bad arguments or input, 77 not available.\n");
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		usage(stderr);
		return PC_EXIT_USAGE;
	}
	if (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help") || !strcmp(argv[1], "help")) {
		usage(stdout);
		return PC_EXIT_OK;
	}
	if (!strcmp(argv[1], "--version") || !strcmp(argv[1], "version")) {
		printf("polarcam %s\n", pc_version());
		return PC_EXIT_OK;
	}
	for (size_t i = 0; i < sizeof pc_commands / sizeof pc_commands[0]; i++) {
		if (strcmp(argv[1], pc_commands[i].name) == 0) {
			pc_cli_command = pc_commands[i].name;
			return pc_commands[i].run(argc - 1, argv + 1);
		}
	}
	fprintf(stderr, "polarcam: error: unknown command '%s'\n\n", argv[1]);
	usage(stderr);
	return PC_EXIT_USAGE;
}
