// kinscene's CasADi shim: rebuilds a Rust expression tape as CasADi SX and drives IPOPT.
#include "shim.h"

#include <casadi/casadi.hpp>
#include <casadi/config.h>

#include <cmath>
#include <string>
#include <vector>

struct ks_casadi_nlp {
    casadi::Function solver;  // nlpsol: (x0, p, lbx, ubx, lbg, ubg, ...) -> (x, f, g, lam_x, ...)
    casadi::Function eval;    // (x, p) -> (f, g)
    std::vector<double> lbx, ubx, lbg, ubg;
    size_t n_x = 0, n_p = 0, n_g = 0;
};

namespace {

using casadi::SXElem;

SXElem unary(int32_t op, const SXElem& a) {
    switch (op) {
        case KS_CASADI_NEG: return SXElem::unary(casadi::OP_NEG, a);
        case KS_CASADI_SIN: return SXElem::unary(casadi::OP_SIN, a);
        case KS_CASADI_COS: return SXElem::unary(casadi::OP_COS, a);
        case KS_CASADI_TAN: return SXElem::unary(casadi::OP_TAN, a);
        case KS_CASADI_ASIN: return SXElem::unary(casadi::OP_ASIN, a);
        case KS_CASADI_ACOS: return SXElem::unary(casadi::OP_ACOS, a);
        case KS_CASADI_ATAN: return SXElem::unary(casadi::OP_ATAN, a);
        case KS_CASADI_SQRT: return SXElem::unary(casadi::OP_SQRT, a);
        case KS_CASADI_EXP: return SXElem::unary(casadi::OP_EXP, a);
        case KS_CASADI_LOG: return SXElem::unary(casadi::OP_LOG, a);
        case KS_CASADI_ABS: return SXElem::unary(casadi::OP_FABS, a);
        case KS_CASADI_TANH: return SXElem::unary(casadi::OP_TANH, a);
        case KS_CASADI_SQ: return SXElem::unary(casadi::OP_SQ, a);
        case KS_CASADI_SINH: return SXElem::unary(casadi::OP_SINH, a);
        case KS_CASADI_COSH: return SXElem::unary(casadi::OP_COSH, a);
        default: throw ks::InvalidArgument("tape: unknown unary op " + std::to_string(op));
    }
}

bool is_binary(int32_t op) { return op >= KS_CASADI_ADD && op <= KS_CASADI_MAX; }

SXElem binary(int32_t op, const SXElem& a, const SXElem& b) {
    switch (op) {
        case KS_CASADI_ADD: return SXElem::binary(casadi::OP_ADD, a, b);
        case KS_CASADI_SUB: return SXElem::binary(casadi::OP_SUB, a, b);
        case KS_CASADI_MUL: return SXElem::binary(casadi::OP_MUL, a, b);
        case KS_CASADI_DIV: return SXElem::binary(casadi::OP_DIV, a, b);
        case KS_CASADI_POW: return SXElem::binary(casadi::OP_POW, a, b);
        case KS_CASADI_ATAN2: return SXElem::binary(casadi::OP_ATAN2, a, b);
        case KS_CASADI_MIN: return SXElem::binary(casadi::OP_FMIN, a, b);
        case KS_CASADI_MAX: return SXElem::binary(casadi::OP_FMAX, a, b);
        default: throw ks::InvalidArgument("tape: unknown binary op " + std::to_string(op));
    }
}

// An earlier node's index, checked.
size_t arg_index(int32_t a, size_t i) {
    if (a < 0 || static_cast<size_t>(a) >= i) {
        throw ks::InvalidArgument("tape: node " + std::to_string(i) + " refers to node " +
                                  std::to_string(a) + ", not an earlier one");
    }
    return static_cast<size_t>(a);
}

std::vector<SXElem> build_nodes(size_t n_nodes, const int32_t* op, const int32_t* arg0,
                                const int32_t* arg1, const double* value,
                                const std::vector<SXElem>& x, const std::vector<SXElem>& p) {
    std::vector<SXElem> v;
    v.reserve(n_nodes);
    for (size_t i = 0; i < n_nodes; ++i) {
        const int32_t o = op[i];
        if (o == KS_CASADI_CONST) {
            v.emplace_back(value[i]);
        } else if (o == KS_CASADI_VAR || o == KS_CASADI_PARAM) {
            const auto& leaves = o == KS_CASADI_VAR ? x : p;
            if (arg0[i] < 0 || static_cast<size_t>(arg0[i]) >= leaves.size()) {
                throw ks::InvalidArgument("tape: leaf index out of range at node " +
                                          std::to_string(i));
            }
            v.push_back(leaves[static_cast<size_t>(arg0[i])]);
        } else if (o == KS_CASADI_POWI) {
            v.push_back(SXElem::binary(casadi::OP_CONSTPOW, v[arg_index(arg0[i], i)],
                                       SXElem(value[i])));
        } else if (is_binary(o)) {
            v.push_back(binary(o, v[arg_index(arg0[i], i)], v[arg_index(arg1[i], i)]));
        } else {
            v.push_back(unary(o, v[arg_index(arg0[i], i)]));
        }
    }
    return v;
}

casadi::Dict build_options(size_t n, const char* const* names, const int32_t* kinds,
                           const double* numbers, const char* const* strings) {
    casadi::Dict opts;
    for (size_t i = 0; i < n; ++i) {
        const std::string name = names[i];
        switch (kinds[i]) {
            case KS_CASADI_OPT_REAL: opts[name] = numbers[i]; break;
            case KS_CASADI_OPT_INT: opts[name] = static_cast<casadi_int>(numbers[i]); break;
            case KS_CASADI_OPT_STRING: opts[name] = std::string(strings[i]); break;
            case KS_CASADI_OPT_BOOL: opts[name] = numbers[i] != 0.0; break;
            default: throw ks::InvalidArgument("option " + name + ": unknown kind");
        }
    }
    return opts;
}

void copy_status(const std::string& s, char* out, size_t len) {
    if (out == nullptr || len == 0) return;
    const size_t n = std::min(s.size(), len - 1);
    std::memcpy(out, s.data(), n);
    out[n] = '\0';
}

void check_sizes(const ks_casadi_nlp* nlp, size_t n_x, size_t n_p) {
    if (nlp == nullptr) throw ks::InvalidArgument("null solver");
    if (n_x != nlp->n_x || n_p != nlp->n_p) {
        throw ks::InvalidArgument("expected " + std::to_string(nlp->n_x) + " variables and " +
                                  std::to_string(nlp->n_p) + " parameters, got " +
                                  std::to_string(n_x) + " and " + std::to_string(n_p));
    }
}

}  // namespace

KS_API const char* ks_casadi_version(void) { return CASADI_VERSION_STRING; }

KS_API int ks_casadi_nlp_new(size_t n_x, size_t n_p, size_t n_nodes, const int32_t* op,
                             const int32_t* arg0, const int32_t* arg1, const double* value,
                             int32_t f_node, size_t n_g, const int32_t* g_nodes,
                             const double* lbx, const double* ubx, const double* lbg,
                             const double* ubg, size_t n_opts, const char* const* opt_names,
                             const int32_t* opt_kinds, const double* opt_numbers,
                             const char* const* opt_strings, ks_casadi_nlp** out, char* err,
                             size_t err_len) {
    return ks::guard(err, err_len, [&] {
        if (out == nullptr) throw ks::InvalidArgument("null output handle");
        *out = nullptr;
        using casadi::SX;
        const SX x = SX::sym("x", static_cast<casadi_int>(n_x));
        const SX p = SX::sym("p", static_cast<casadi_int>(n_p));
        const std::vector<SXElem> v =
            build_nodes(n_nodes, op, arg0, arg1, value, x.nonzeros(), p.nonzeros());
        auto node = [&](int32_t i) -> const SXElem& {
            if (i < 0 || static_cast<size_t>(i) >= v.size()) {
                throw ks::InvalidArgument("output refers to a node outside the tape");
            }
            return v[static_cast<size_t>(i)];
        };
        const SX f = f_node < 0 ? SX(0.0) : SX(node(f_node));
        std::vector<SXElem> g_elems;
        g_elems.reserve(n_g);
        for (size_t i = 0; i < n_g; ++i) g_elems.push_back(node(g_nodes[i]));
        const SX g = n_g == 0 ? SX(0, 1) : SX(g_elems);

        auto nlp = std::make_unique<ks_casadi_nlp>();
        nlp->n_x = n_x;
        nlp->n_p = n_p;
        nlp->n_g = n_g;
        nlp->lbx.assign(lbx, lbx + n_x);
        nlp->ubx.assign(ubx, ubx + n_x);
        nlp->lbg.assign(lbg, lbg + n_g);
        nlp->ubg.assign(ubg, ubg + n_g);
        const casadi::Dict opts =
            build_options(n_opts, opt_names, opt_kinds, opt_numbers, opt_strings);
        nlp->solver = casadi::nlpsol("kinscene_nlp", "ipopt",
                                     casadi::SXDict{{"x", x}, {"p", p}, {"f", f}, {"g", g}}, opts);
        nlp->eval = casadi::Function("kinscene_eval", {x, p}, {f, g}, {"x", "p"}, {"f", "g"});
        *out = nlp.release();
    });
}

KS_API void ks_casadi_nlp_free(ks_casadi_nlp* nlp) {
    // Destructors of casadi objects do not throw; guard anyway so nothing escapes.
    char err[1];
    ks::guard(err, 1, [&] { delete nlp; });
}

KS_API int ks_casadi_nlp_solve(const ks_casadi_nlp* nlp, size_t n_x, const double* x0, size_t n_p,
                               const double* p, double* x, double* f, double* g, double* lam_x,
                               double* lam_g, char* status, size_t status_len,
                               int64_t* iterations, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        check_sizes(nlp, n_x, n_p);
        const casadi::Function& s = nlp->solver;
        std::vector<const double*> arg(s.sz_arg(), nullptr);
        std::vector<double*> res(s.sz_res(), nullptr);
        arg[casadi::NLPSOL_X0] = x0;
        arg[casadi::NLPSOL_P] = p;
        arg[casadi::NLPSOL_LBX] = nlp->lbx.data();
        arg[casadi::NLPSOL_UBX] = nlp->ubx.data();
        arg[casadi::NLPSOL_LBG] = nlp->lbg.data();
        arg[casadi::NLPSOL_UBG] = nlp->ubg.data();
        res[casadi::NLPSOL_X] = x;
        res[casadi::NLPSOL_F] = f;
        res[casadi::NLPSOL_G] = g;
        res[casadi::NLPSOL_LAM_X] = lam_x;
        res[casadi::NLPSOL_LAM_G] = lam_g;
        std::vector<casadi_int> iw(s.sz_iw());
        std::vector<double> w(s.sz_w());
        // Own memory object per call, so the statistics read below are this solve's.
        const int mem = static_cast<int>(s.checkout());
        struct Release {
            const casadi::Function& s;
            int mem;
            ~Release() { s.release(mem); }
        } release{s, mem};
        s(arg.data(), res.data(), iw.data(), w.data(), mem);
        const casadi::Dict stats = s.stats(mem);
        const auto st = stats.find("return_status");
        copy_status(st == stats.end() ? std::string("unknown") : st->second.to_string(), status,
                    status_len);
        const auto it = stats.find("iter_count");
        *iterations = it == stats.end() ? -1 : static_cast<int64_t>(it->second.to_int());
    });
}

KS_API int ks_casadi_nlp_eval(const ks_casadi_nlp* nlp, size_t n_x, const double* x, size_t n_p,
                              const double* p, double* f, double* g, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        check_sizes(nlp, n_x, n_p);
        nlp->eval(std::vector<const double*>{x, p}, std::vector<double*>{f, g});
    });
}
