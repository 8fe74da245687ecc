/* Without Aravis: the GigE Vision server is not available. */
#include "polarcam/error.h"
#include "polarcam/gige_server.h"

#include <string.h>

int pc_gige_server_start(pc_gige_server **out, const pc_gige_server_options *opt)
{
	(void)opt;
	if (out)
		*out = NULL;
	return pc_error(PC_EUNAVAIL, "serve: built without Aravis (Debian: libaravis-dev, then "
	                             "re-run cmake)");
}

void pc_gige_server_get_stats(pc_gige_server *srv, pc_gige_server_stats *st)
{
	(void)srv;
	memset(st, 0, sizeof *st);
}

int pc_gige_server_error(pc_gige_server *srv, char *msg, unsigned size)
{
	(void)srv;
	if (msg && size)
		msg[0] = '\0';
	return 0;
}

const char *pc_gige_server_genicam(pc_gige_server *srv)
{
	(void)srv;
	return NULL;
}

void pc_gige_server_stop(pc_gige_server *srv)
{
	(void)srv;
}

void pc_devices_shutdown(void)
{
}
