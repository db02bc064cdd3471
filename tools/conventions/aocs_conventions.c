/*
 * Host tool: evaluates the firmware's attitude conventions (SPEC 1) on the
 * numbers given on stdin, one request per line, and prints the results with
 * 17 significant digits, so the Python conventions module
 * (sil/aocs_core/conventions.py) can be tested against the C code it mirrors
 * (tests/python/aocs_core/test_conventions.py). Not flight code.
 *
 *   mul q1 q2 q3 q4 p1 p2 p3 p4   -> q (x) p           (4 numbers)
 *   err q1..q4 qd1..qd4           -> q (x) qd^-1       (4)
 *   dcm q1..q4                    -> A(q), row-major    (9)
 *   e2q yaw pitch roll            -> q of Euler 3-2-1   (4)
 *   q2e q1..q4                    -> yaw pitch roll     (3)
 *   crp q1..q4                    -> rho, or "singular" (3)
 *   mrp q1..q4                    -> sigma, |sigma| <= 1 (3)
 *   angle q1..q4                  -> rotation angle, rad (1)
 * A malformed line prints "error" and the tool goes on; exit 0 at EOF.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aocs/attitude.h"

#define LINE_MAX_CHARS 1024
#define ARGS_MAX 8

static int parse_numbers(char *text, double *out, int want)
{
    int n = 0;
    char *tok = strtok(text, " \t\r\n");
    while ((tok != NULL) && (n < ARGS_MAX)) {
        char *end = NULL;
        out[n] = strtod(tok, &end);
        if ((end == tok) || (*end != '\0')) {
            return -1;
        }
        ++n;
        tok = strtok(NULL, " \t\r\n");
    }
    return ((n == want) && (tok == NULL)) ? 0 : -1;
}

static aocs_quat_t quat_at(const double *a)
{
    return aocs_quat_make((real_t)a[0], (real_t)a[1], (real_t)a[2], (real_t)a[3]);
}

static void print_values(const real_t *v, int n)
{
    for (int i = 0; i < n; ++i) {
        printf("%s%.17g", (i == 0) ? "" : " ", (double)v[i]);
    }
    printf("\n");
}

static int evaluate(const char *op, char *rest)
{
    double a[ARGS_MAX];
    int ok = -1;
    if (strcmp(op, "mul") == 0 || strcmp(op, "err") == 0) {
        if (parse_numbers(rest, a, 8) == 0) {
            aocs_quat_t r = (op[0] == 'm') ? aocs_quat_mul(quat_at(a), quat_at(a + 4))
                                           : aocs_quat_error(quat_at(a), quat_at(a + 4));
            print_values(r.q, 4);
            ok = 0;
        }
    } else if (strcmp(op, "dcm") == 0) {
        if (parse_numbers(rest, a, 4) == 0) {
            aocs_mat3_t m = aocs_quat_to_dcm(quat_at(a));
            print_values(&m.m[0][0], 3);
            print_values(&m.m[1][0], 3);
            print_values(&m.m[2][0], 3);
            ok = 0;
        }
    } else if (strcmp(op, "e2q") == 0) {
        if (parse_numbers(rest, a, 3) == 0) {
            aocs_euler321_t e = {(real_t)a[0], (real_t)a[1], (real_t)a[2]};
            aocs_quat_t q = aocs_euler321_to_quat(e);
            print_values(q.q, 4);
            ok = 0;
        }
    } else if (strcmp(op, "q2e") == 0) {
        if (parse_numbers(rest, a, 4) == 0) {
            aocs_euler321_t e = aocs_quat_to_euler321(quat_at(a));
            real_t v[3] = {e.yaw, e.pitch, e.roll};
            print_values(v, 3);
            ok = 0;
        }
    } else if (strcmp(op, "crp") == 0) {
        if (parse_numbers(rest, a, 4) == 0) {
            aocs_vec3_t rho;
            if (aocs_quat_to_crp(quat_at(a), &rho) == AOCS_OK) {
                print_values(rho.v, 3);
            } else {
                printf("singular\n");
            }
            ok = 0;
        }
    } else if (strcmp(op, "mrp") == 0) {
        if (parse_numbers(rest, a, 4) == 0) {
            aocs_vec3_t s = aocs_quat_to_mrp(quat_at(a));
            print_values(s.v, 3);
            ok = 0;
        }
    } else if (strcmp(op, "angle") == 0) {
        if (parse_numbers(rest, a, 4) == 0) {
            real_t ang = aocs_quat_angle(quat_at(a));
            print_values(&ang, 1);
            ok = 0;
        }
    } else {
        ok = -1;
    }
    return ok;
}

int main(void)
{
    char line[LINE_MAX_CHARS];
    while (fgets(line, (int)sizeof line, stdin) != NULL) {
        char *space = strpbrk(line, " \t");
        if (space == NULL) {
            printf("error\n");
        } else {
            *space = '\0';
            if (evaluate(line, space + 1) != 0) {
                printf("error\n");
            }
        }
        fflush(stdout);
    }
    return 0;
}
