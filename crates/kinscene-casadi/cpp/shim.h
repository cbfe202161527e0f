// C ABI of kinscene's CasADi shim: build an NLP from an expression tape and solve it with IPOPT.
//
// The Rust side (crate kinscene-casadi, src/ffi.rs) declares these signatures by hand; keep the
// two in sync. Conventions (ks_common.h): every fallible function returns a ks_status and takes
// (char* err, size_t err_len) last; no C++ exception escapes.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "ks_common.h"

// Tape operation codes. A tape is a topologically ordered list of nodes; node i is
// (op[i], arg0[i], arg1[i], value[i]) and its arguments are indices of earlier nodes.
enum ks_casadi_op : int32_t {
    KS_CASADI_CONST = 0,  // value
    KS_CASADI_VAR = 1,    // decision variable number arg0
    KS_CASADI_PARAM = 2,  // parameter number arg0
    // unary: f(arg0)
    KS_CASADI_NEG = 10,
    KS_CASADI_SIN = 11,
    KS_CASADI_COS = 12,
    KS_CASADI_TAN = 13,
    KS_CASADI_ASIN = 14,
    KS_CASADI_ACOS = 15,
    KS_CASADI_ATAN = 16,
    KS_CASADI_SQRT = 17,
    KS_CASADI_EXP = 18,
    KS_CASADI_LOG = 19,
    KS_CASADI_ABS = 20,
    KS_CASADI_TANH = 21,
    KS_CASADI_SQ = 22,
    KS_CASADI_SINH = 23,
    KS_CASADI_COSH = 24,
    // binary: f(arg0, arg1)
    KS_CASADI_ADD = 40,
    KS_CASADI_SUB = 41,
    KS_CASADI_MUL = 42,
    KS_CASADI_DIV = 43,
    KS_CASADI_POW = 44,
    KS_CASADI_ATAN2 = 45,  // atan2(arg0 = y, arg1 = x)
    KS_CASADI_MIN = 46,
    KS_CASADI_MAX = 47,
    // arg0 raised to the integer power value
    KS_CASADI_POWI = 60,
};

// Kinds of solver options (ks_casadi_nlp_new).
enum ks_casadi_opt_kind : int32_t {
    KS_CASADI_OPT_REAL = 0,    // number
    KS_CASADI_OPT_INT = 1,     // number, an exact integer
    KS_CASADI_OPT_STRING = 2,  // string
    KS_CASADI_OPT_BOOL = 3,    // number, non-zero = true
};

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ks_casadi_nlp ks_casadi_nlp;

// The CasADi version the shim was compiled against (static string).
KS_API const char* ks_casadi_version(void);

// Builds an NLP  min f(x, p)  s.t.  lbx <= x <= ubx,  lbg <= g(x, p) <= ubg  and creates the
// IPOPT solver (casadi::nlpsol) once.
//   tape:     n_nodes entries of op, arg0, arg1, value (see ks_casadi_op)
//   f_node:   node of the objective, or -1 for f = 0
//   g_nodes:  n_g nodes, the constraint functions
//   lbx, ubx: n_x variable bounds; lbg, ubg: n_g constraint bounds (+-inf allowed)
//   options:  n_opts entries of name, kind, number, string, passed to casadi::nlpsol as a Dict
//             (IPOPT options carry the prefix "ipopt.")
// On success *out owns the solver; free it with ks_casadi_nlp_free.
KS_API int ks_casadi_nlp_new(size_t n_x, size_t n_p, size_t n_nodes, const int32_t* op,
                             const int32_t* arg0, const int32_t* arg1, const double* value,
                             int32_t f_node, size_t n_g, const int32_t* g_nodes,
                             const double* lbx, const double* ubx, const double* lbg,
                             const double* ubg, size_t n_opts, const char* const* opt_names,
                             const int32_t* opt_kinds, const double* opt_numbers,
                             const char* const* opt_strings, ks_casadi_nlp** out, char* err,
                             size_t err_len);

// Frees a solver (null is allowed).
KS_API void ks_casadi_nlp_free(ks_casadi_nlp* nlp);

// Solves from the initial guess x0 (n_x) with parameter values p (n_p). Writes x, lam_x (n_x),
// g, lam_g (n_g), f, IPOPT's return_status into status (NUL-terminated, truncated to
// status_len) and the iteration count. Non-convergence is not an error.
KS_API int ks_casadi_nlp_solve(const ks_casadi_nlp* nlp, size_t n_x, const double* x0, size_t n_p,
                               const double* p, double* x, double* f, double* g, double* lam_x,
                               double* lam_g, char* status, size_t status_len,
                               int64_t* iterations, char* err, size_t err_len);

// Evaluates f and g (n_g) at (x, p) with CasADi's own evaluator.
KS_API int ks_casadi_nlp_eval(const ks_casadi_nlp* nlp, size_t n_x, const double* x, size_t n_p,
                              const double* p, double* f, double* g, char* err, size_t err_len);

#ifdef __cplusplus
}
#endif
