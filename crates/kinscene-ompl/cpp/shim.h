// kinscene OMPL shim: a C ABI over OMPL 1.5 geometric planning.
//
// Conventions (ks_common.h): every fallible function returns a ks_status and takes
// (char* err, size_t err_len) last; no C++ exception crosses this boundary.
// The Rust declarations in src/ffi.rs mirror this header exactly; change both together.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "ks_common.h"

// Path simplification (ks_ompl_plan_request::simplify).
enum {
    KS_OMPL_SIMPLIFY_OFF = 0,       // none
    KS_OMPL_SIMPLIFY_FULL = 1,      // PathSimplifier::simplify with the remaining time
    KS_OMPL_SIMPLIFY_SHORTCUT = 2,  // one reduceVertices and one shortcutPath pass
};

// State spaces.
enum { KS_OMPL_SPACE_SE2 = 0, KS_OMPL_SPACE_REAL_VECTOR = 1 };

// Geometric planners.
enum {
    KS_OMPL_RRT_CONNECT = 0,
    KS_OMPL_RRT = 1,
    KS_OMPL_RRT_STAR = 2,
    KS_OMPL_PRM = 3,
    KS_OMPL_PRM_STAR = 4,
    KS_OMPL_KPIECE1 = 5,
    KS_OMPL_BKPIECE1 = 6,
    KS_OMPL_LBKPIECE1 = 7,
    KS_OMPL_EST = 8,
    KS_OMPL_SBL = 9,
    KS_OMPL_BIT_STAR = 10,
};

// State validity: returns non-zero when `state` (dim values; SE(2): x, y, yaw) is valid.
// May be called from several threads at once (OMPL's PRM grows its roadmap in a second thread).
typedef int (*ks_ompl_validity_fn)(void* user, const double* state, size_t dim);
// Motion validity: returns non-zero when the motion from `a` to `b` (dim values each, same
// layout as the validity callback; the space's interpolation: straight lines, shortest angle
// for the SE(2) yaw) is valid, `b` included. `a` is a state OMPL already holds as valid. Called
// from the same threads as the validity callback.
typedef int (*ks_ompl_motion_fn)(void* user, const double* a, const double* b, size_t dim);
// Cancellation: returns non-zero when planning should stop. Polled often; must be cheap.
typedef int (*ks_ompl_cancel_fn)(void* user);
// Receives the solution path, one state at a time, in order.
typedef void (*ks_ompl_path_sink)(void* user, const double* state, size_t dim);

typedef struct ks_ompl_plan_request {
    int32_t space;             // KS_OMPL_SPACE_*
    int32_t planner;           // KS_OMPL_* planner
    size_t dim;                // state dimension: 3 for SE(2)
    size_t bounds_len;         // 2 for SE(2) (x, y), dim for a real vector space
    const double* lower;       // bounds_len lower bounds
    const double* upper;       // bounds_len upper bounds
    const double* start;       // dim values
    const double* goal;        // dim values
    double goal_tolerance;     // OMPL state-space distance
    double range;              // planner range; <= 0: the planner's default
    double resolution;         // setStateValidityCheckingResolution, fraction of the max extent
    double budget_s;           // time budget in seconds (planning + simplification)
    int32_t simplify;          // KS_OMPL_SIMPLIFY_*
    uint32_t interpolate_to;   // PathGeometric::interpolate(count) when > 0
    int32_t has_cost_threshold;// non-zero: path-length objective with cost_threshold
    double cost_threshold;
    uint64_t max_iterations;   // > 0: solve() also ends after this many termination checks
} ks_ompl_plan_request;

typedef struct ks_ompl_plan_result {
    int32_t status;            // ompl::base::PlannerStatus::StatusType
    double planning_time_s;    // setup + solve
    double simplification_time_s;
    double goal_distance;      // distance of the path's last state to the goal; NaN if no path
    uint64_t iterations;       // termination checks made by solve() (about one per iteration)
} ks_ompl_plan_result;

// Plans one query. `cancel` may be NULL. `motion` may be NULL: OMPL's discrete motion
// validator then checks motions with `valid` every `resolution`; otherwise `motion` decides
// every motion (planner and simplifier) and `resolution` is unused. The path (if any) goes to `sink` before returning.
// The start and goal are checked (bounds, then validity) before a planner is built, so every
// planner reports INVALID_START / INVALID_GOAL the same way.
KS_API int ks_ompl_plan(const ks_ompl_plan_request* request, ks_ompl_validity_fn valid,
                        void* valid_user, ks_ompl_motion_fn motion, void* motion_user,
                        ks_ompl_cancel_fn cancel, void* cancel_user,
                        ks_ompl_path_sink sink, void* sink_user, ks_ompl_plan_result* out,
                        char* err, size_t err_len);

// ompl::RNG::setSeed (0 is replaced by 1, which OMPL would do with a warning).
KS_API int ks_ompl_set_seed(uint64_t seed, char* err, size_t err_len);

// ompl::msg::setLogLevel with an ompl::msg::LogLevel value (-2 .. 4).
KS_API int ks_ompl_set_log_level(int32_t level, char* err, size_t err_len);

// ----- benchmark support only -----
typedef struct ks_ompl_bench_result {
    uint64_t callback_ns;      // total time of passes * n_states isValid calls, Rust callback
    uint64_t cpp_ns;           // the same with the C++ disc checker
    uint64_t callback_valid;   // valid states counted in one pass, Rust callback
    uint64_t cpp_valid;        // valid states counted in one pass, C++ checker
} ks_ompl_bench_result;

// Samples n_states uniformly in [0,1]^2, then times `passes` sweeps of
// SpaceInformation::isValid over them with (a) `valid` as the checker and (b) a C++ checker
// that accepts states outside the disc (cx, cy, radius): (x-cx)^2 + (y-cy)^2 > radius^2.
KS_API int ks_ompl_bench_validity(double cx, double cy, double radius, size_t n_states,
                                  size_t passes, ks_ompl_validity_fn valid, void* valid_user,
                                  ks_ompl_bench_result* out, char* err, size_t err_len);
