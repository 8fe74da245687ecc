/* The CLI's number parsing and message quoting (tools/cli.c, issue 13): integers are decimal
 * (010 is ten, never octal eight; 0x10 and junk after the digits are refused), out-of-range
 * values are refused with the valid range in the message, subnormal doubles are kept (and
 * underflow to 0 is refused), batch fields are parsed whole however long (a number followed by
 * 130 zeros and 'junk' used to be cut at 127 bytes and accepted), NUL bytes in a batch line are
 * refused, and control bytes are escaped in messages. */
#include <float.h>
#include <limits.h>
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "cli.h"
#include "polarcam/error.h"

static void test_integers(void)
{
	uint64_t u = 0;
	long l = 0;
	CHECK_EQ_INT(cli_parse_u64("--seed", "010", &u), 0);
	CHECK(u == 10);
	CHECK_EQ_INT(cli_parse_u64("--seed", "18446744073709551615", &u), 0);
	CHECK(u == UINT64_MAX);
	static const char *const junk[] = {"0x10", "10junk", " 5",  "+5",    "-1",          "5 ",
	                                   "1e3",  "",       "0b1", "1,000", "\xef\xbc\x91"};
	for (size_t i = 0; i < sizeof junk / sizeof junk[0]; i++) {
		CHECK_EQ_INT(cli_parse_u64("--seed", junk[i], &u), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "--seed") != NULL);
	}
	CHECK_EQ_INT(cli_parse_u64("--seed", "18446744073709551616", &u), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "[0, 18446744073709551615]") != NULL);
	CHECK_EQ_INT(cli_parse_u64_range("--first", "9223372036854775808", 0, INT64_MAX, &u),
	             PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "[0, 9223372036854775807]") != NULL);
	CHECK_EQ_INT(cli_parse_u64_range("--first", "9223372036854775807", 0, INT64_MAX, &u), 0);
	/* overflow followed by junk is still reported as junk */
	CHECK_EQ_INT(cli_parse_u64("--seed", "99999999999999999999x", &u), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "not a non-negative integer") != NULL);

	CHECK_EQ_INT(cli_parse_long("--threads", "08", 1, 1024, &l), 0);
	CHECK_EQ_INT(l, 8);
	CHECK_EQ_INT(cli_parse_long("--threads", "1025", 1, 1024, &l), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "[1, 1024]") != NULL);
	CHECK_EQ_INT(cli_parse_long("--threads", "0", 1, 1024, &l), PC_EINVAL);
	CHECK_EQ_INT(cli_parse_long("--threads", "-3", 1, 1024, &l), PC_EINVAL);
	CHECK_EQ_INT(cli_parse_long("--x", "-3", -5, 5, &l), 0);
	CHECK_EQ_INT(l, -3);
	CHECK_EQ_INT(cli_parse_long("--x", "-9223372036854775808", LONG_MIN, LONG_MAX, &l), 0);
	CHECK(l == LONG_MIN);
	CHECK_EQ_INT(cli_parse_long("--x", "-9223372036854775809", LONG_MIN, LONG_MAX, &l),
	             PC_EINVAL);
	CHECK_EQ_INT(cli_parse_long("--x", "9223372036854775808", LONG_MIN, LONG_MAX, &l),
	             PC_EINVAL);
	CHECK_EQ_INT(cli_parse_long("--x", "--3", -5, 5, &l), PC_EINVAL);
	CHECK_EQ_INT(cli_parse_long("--x", "-", -5, 5, &l), PC_EINVAL);
}

static void test_doubles(void)
{
	double v = 0;
	CHECK_EQ_INT(cli_parse_double("--sigma", "1e-320", &v), 0); /* subnormal: kept */
	CHECK(v > 0 && v < DBL_MIN);
	CHECK_EQ_INT(cli_parse_double("--sigma", "1e-400", &v), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "smallest double") != NULL);
	CHECK_EQ_INT(cli_parse_double("--sigma", "1e400", &v), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "finite") != NULL);
	CHECK_EQ_INT(cli_parse_double("--sigma", "nan", &v), PC_EINVAL);
	CHECK_EQ_INT(cli_parse_double("--sigma", "0.5x", &v), PC_EINVAL);
	CHECK_EQ_INT(cli_parse_double("--sigma", "0", &v), 0);
	CHECK(v == 0);
	CHECK_EQ_INT(cli_parse_double("--sigma", "-0.0e-999", &v), 0); /* zero digits: zero */
}

static void test_fields(void)
{
	static const char *const names[6] = {"n", "k", "sigma", "theta_i", "theta_r", "phi"};
	double out[6];
	/* '1' then 130 zeros then 'junk': the whole token is read and refused */
	char line[256];
	int o = snprintf(line, sizeof line, "1.5 0 0.2 30 30 1");
	memset(line + o, '0', 130);
	strcpy(line + o + 130, "junk");
	CHECK_EQ_INT(cli_parse_fields(line, names, 6, out), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "field 6 (phi)") && strstr(pc_error_detail(), "junk"));
	/* the same digits without junk: a (large) number */
	line[o + 130] = '\0';
	CHECK_EQ_INT(cli_parse_fields(line, names, 6, out), 0);
	CHECK_REL(out[5], 1e130, 1e-15);
	/* a NUL byte inside the line: refused, naming the byte */
	const char nul[] = "1.5 0 0.2 30 30 180\0junk";
	CHECK_EQ_INT(cli_parse_fields_n(nul, sizeof nul - 1, names, 6, out), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "byte 20") != NULL);
	CHECK_EQ_INT(cli_parse_fields_n(nul, 19, names, 6, out), 0);
	CHECK_EQ_INT(cli_parse_fields("1 2 3", names, 6, out), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "got 3") != NULL);
}

static void test_quote(void)
{
	char q[64];
	/* control bytes (ESC of a colour sequence, NUL-free binary) become \xNN; UTF-8 stays */
	cli_quote("a\x1b[31mb\x01\x7f", 9, q, sizeof q);
	CHECK(strcmp(q, "a\\x1b[31mb\\x01\\x7f") == 0);
	cli_quote("caf\xc3\xa9", 5, q, sizeof q);
	CHECK(strcmp(q, "caf\xc3\xa9") == 0);
	cli_quote("\xc3(", 2, q, sizeof q); /* broken UTF-8 */
	CHECK(strcmp(q, "\\xc3(") == 0);
	/* overlong (E0 9A B0, found by fuzz_batch_decompose: jansson refused the error object),
	 * a surrogate (ED A0 80), beyond U+10FFFF (F4 90 80 80); U+10FFFF itself is kept */
	cli_quote("\xe0\x9a\xb0|\xed\xa0\x80|\xf4\x90\x80\x80|\xf4\x8f\xbf\xbf", 17, q, sizeof q);
	CHECK(strcmp(q, "\\xe0\\x9a\\xb0|\\xed\\xa0\\x80|\\xf4\\x90\\x80\\x80|\xf4\x8f\xbf\xbf") ==
	      0);
	const char zero[3] = {'a', 0, 'b'};
	cli_quote(zero, 3, q, sizeof q);
	CHECK(strcmp(q, "a\\x00b") == 0);
	/* cut to fit, marked with "..." */
	char small[12];
	cli_quote("0123456789abcdef", 16, small, sizeof small);
	CHECK(strcmp(small, "01234567...") == 0);
	cli_quote("\x01\x02\x03", 3, small, sizeof small);
	CHECK(strcmp(small, "\\x01\\x02...") == 0);
	/* the batch error object is valid JSON (UTF-8) even for binary input */
	pc_error(PC_EINVAL, "field 1 '\xff\xfe\x1b'");
	json_t *j = cli_json_error_line(3, PC_EINVAL);
	CHECK(j != NULL);
	if (j) {
		const char *e = json_string_value(json_object_get(j, "error"));
		CHECK(e && strstr(e, "\\xff\\xfe\\x1b"));
		json_decref(j);
	}
}

int main(void)
{
	test_integers();
	test_doubles();
	test_fields();
	test_quote();
	return pc_test_finish("test_cli_parse");
}
