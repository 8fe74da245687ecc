#include "polarcam/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#define PC_DETAIL_MAX 1024
static _Thread_local char pc_detail[PC_DETAIL_MAX];

const char *pc_strerror(int code)
{
	switch (code) {
	case PC_OK:
		return "success";
#define PC_ERRNO_TEXT(name, value, text)                                                           \
	case name:                                                                                 \
		return text;
		PC_ERRNO_MAP(PC_ERRNO_TEXT)
#undef PC_ERRNO_TEXT
	default:
		return "unknown error";
	}
}

const char *pc_errname(int code)
{
	switch (code) {
	case PC_OK:
		return "PC_OK";
#define PC_ERRNO_NAME(name, value, text)                                                           \
	case name:                                                                                 \
		return #name;
		PC_ERRNO_MAP(PC_ERRNO_NAME)
#undef PC_ERRNO_NAME
	default:
		return "PC_EUNKNOWN";
	}
}

int pc_error(int code, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(pc_detail, sizeof pc_detail, fmt, ap);
	va_end(ap);
	return code;
}

int pc_error_prefix(int code, const char *fmt, ...)
{
	char prefix[PC_DETAIL_MAX];
	char old[PC_DETAIL_MAX];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(prefix, sizeof prefix, fmt, ap);
	va_end(ap);
	memcpy(old, pc_detail, sizeof old);
	size_t np = strlen(prefix), no = strlen(old);
	if (np > PC_DETAIL_MAX - 1)
		np = PC_DETAIL_MAX - 1;
	if (no > PC_DETAIL_MAX - 1 - np)
		no = PC_DETAIL_MAX - 1 - np;
	memcpy(pc_detail, prefix, np);
	memcpy(pc_detail + np, old, no);
	pc_detail[np + no] = '\0';
	return code;
}

const char *pc_error_detail(void)
{
	return pc_detail;
}

void pc_error_clear(void)
{
	pc_detail[0] = '\0';
}
