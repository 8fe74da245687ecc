#include "polarcam/version.h"

const char *pc_version(void)
{
	return PC_VERSION_STRING;
}

/* The compiler's own version macros: clang defines __GNUC__ too, so it is tested first. */
#define PC_STR_(x) #x
#define PC_STR(x)  PC_STR_(x)
#if defined(__clang__)
#define PC_BUILD_COMPILER                                                                          \
	"clang " PC_STR(__clang_major__) "." PC_STR(__clang_minor__) "." PC_STR(                   \
	    __clang_patchlevel__)
#elif defined(__GNUC__)
#define PC_BUILD_COMPILER                                                                          \
	"GCC " PC_STR(__GNUC__) "." PC_STR(__GNUC_MINOR__) "." PC_STR(__GNUC_PATCHLEVEL__)
#else
#define PC_BUILD_COMPILER "unknown C compiler"
#endif

const char *pc_build_compiler(void)
{
	return PC_BUILD_COMPILER;
}
