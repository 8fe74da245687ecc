#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/version.h"

static const cli_command cli_commands[] = {
#define CLI_COMMAND_ENTRY(name, summary) {#name, summary, cli_cmd_##name},
    CLI_COMMANDS(CLI_COMMAND_ENTRY)
#undef CLI_COMMAND_ENTRY
};

static void usage(FILE *fp)
{
	fprintf(fp, "usage: polarcam COMMAND [OPTIONS]   (polarcam COMMAND --help for details)\n\n"
	            "Simulate and process division-of-focal-plane polarization cameras.\n\n"
	            "commands:\n");
	for (size_t i = 0; i < sizeof cli_commands / sizeof cli_commands[0]; i++)
		fprintf(fp, "  %-10s %s\n", cli_commands[i].name, cli_commands[i].summary);
	fprintf(
	    fp,
	    "\nEvery command: --help (with examples), --quiet/-q (errors only on stderr), --json\n"
	    "(results as JSON lines on stdout) where it reports, --overwrite where it writes.\n"
	    "stdout carries results only; progress, messages and errors go to stderr.\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or input (also: the output\n"
	    "exists, use --overwrite), 77 not available (backend not built, device or display\n"
	    "absent).\n");
	fprintf(fp,
	        "\nLimits on untrusted input (docs/reliability.md), sizes like 400M or 4Gi:\n"
	        "  POLARCAM_MAX_PIXELS     pixels of one image or scene (default 100M)\n"
	        "  POLARCAM_MAX_BYTES      bytes of one decoded image or array (default 4Gi)\n"
	        "  POLARCAM_MAX_TRIANGLES  triangles of one mesh (default 16Mi)\n"
	        "  POLARCAM_MAX_FRAMES     frames of one recording (default 999999)\n"
	        "  POLARCAM_MAX_MEMORY     memory a render may use (default: what is available)\n");
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		usage(stderr);
		return CLI_EXIT_USAGE;
	}
	if (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help") || !strcmp(argv[1], "help")) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	if (!strcmp(argv[1], "--version") || !strcmp(argv[1], "version")) {
		printf("polarcam %s (library built by %s)\n", pc_version(), pc_build_compiler());
		return CLI_EXIT_OK;
	}
	/* --quiet / -q belongs to every command: taken out here (up to a "--") */
	int n = 2;
	for (int i = 2; i < argc; i++) {
		if (!strcmp(argv[i], "--")) {
			while (i < argc)
				argv[n++] = argv[i++];
			break;
		}
		if (!strcmp(argv[i], "--quiet") || !strcmp(argv[i], "-q"))
			cli_quiet = true;
		else
			argv[n++] = argv[i];
	}
	argc = n;
	argv[argc] = NULL;
	for (size_t i = 0; i < sizeof cli_commands / sizeof cli_commands[0]; i++) {
		if (strcmp(argv[1], cli_commands[i].name) == 0) {
			cli_name = cli_commands[i].name;
			return cli_commands[i].run(argc - 1, argv + 1);
		}
	}
	fprintf(stderr, "polarcam: error: unknown command '%s'\n\n", argv[1]);
	usage(stderr);
	return CLI_EXIT_USAGE;
}
