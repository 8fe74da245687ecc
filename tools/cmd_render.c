#include "cli.h"
#include "commands.h"

/* Placeholder until issue 4 lands this command. */
int cmd_render(int argc, char **argv)
{
	(void)argc;
	(void)argv;
	return pc_cli_error(PC_EXIT_FAILURE, "not implemented yet (issue 4)");
}
