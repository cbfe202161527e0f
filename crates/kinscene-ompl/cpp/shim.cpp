// kinscene OMPL shim: see shim.h for the C ABI and its conventions.
#include "shim.h"

#include <ompl/base/MotionValidator.h>
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/samplers/InformedStateSampler.h>
#include <ompl/base/spaces/RealVectorStateProjections.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/est/EST.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/kpiece/BKPIECE1.h>
#include <ompl/geometric/planners/kpiece/KPIECE1.h>
#include <ompl/geometric/planners/kpiece/LBKPIECE1.h>
#include <ompl/geometric/planners/prm/PRM.h>
#include <ompl/geometric/planners/prm/PRMstar.h>
#include <ompl/geometric/planners/rrt/RRT.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/geometric/planners/sbl/SBL.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Copies an OMPL state into the flat layout the Rust side sees ([x, y, yaw] for SE(2)).
void to_flat(bool se2, const ob::State* s, size_t dim, double* out) {
    if (se2) {
        const auto* st = s->as<ob::SE2StateSpace::StateType>();
        out[0] = st->getX();
        out[1] = st->getY();
        out[2] = st->getYaw();
    } else {
        const double* v = s->as<ob::RealVectorStateSpace::StateType>()->values;
        for (size_t i = 0; i < dim; ++i) out[i] = v[i];
    }
}

// The state validity checker that calls back into Rust.
class CallbackChecker final : public ob::StateValidityChecker {
public:
    CallbackChecker(ob::SpaceInformation* si, bool se2, size_t dim, ks_ompl_validity_fn fn,
                    void* user)
        : ob::StateValidityChecker(si), se2_(se2), dim_(dim), fn_(fn), user_(user) {}

    bool isValid(const ob::State* s) const override {
        if (se2_) {
            double q[3];
            to_flat(true, s, 3, q);
            return fn_(user_, q, 3) != 0;
        }
        return fn_(user_, s->as<ob::RealVectorStateSpace::StateType>()->values, dim_) != 0;
    }

private:
    bool se2_;
    size_t dim_;
    ks_ompl_validity_fn fn_;
    void* user_;
};

// The motion validator that calls back into Rust.
class CallbackMotionValidator final : public ob::MotionValidator {
public:
    CallbackMotionValidator(ob::SpaceInformation* si, bool se2, size_t dim, ks_ompl_motion_fn fn,
                            void* user)
        : ob::MotionValidator(si), se2_(se2), dim_(dim), fn_(fn), user_(user) {}

    bool checkMotion(const ob::State* s1, const ob::State* s2) const override {
        const bool ok = call(s1, s2);
        ++(ok ? valid_ : invalid_);
        return ok;
    }

    // The callback gives no position along a rejected motion: the last valid state reported
    // is `s1` (fraction 0), which OMPL holds as valid.
    bool checkMotion(const ob::State* s1, const ob::State* s2,
                     std::pair<ob::State*, double>& last_valid) const override {
        if (checkMotion(s1, s2)) return true;
        if (last_valid.first) si_->copyState(last_valid.first, s1);
        last_valid.second = 0.0;
        return false;
    }

private:
    bool call(const ob::State* s1, const ob::State* s2) const {
        if (se2_) {
            double a[3], b[3];
            to_flat(true, s1, 3, a);
            to_flat(true, s2, 3, b);
            return fn_(user_, a, b, 3) != 0;
        }
        return fn_(user_, s1->as<ob::RealVectorStateSpace::StateType>()->values,
                   s2->as<ob::RealVectorStateSpace::StateType>()->values, dim_) != 0;
    }

    bool se2_;
    size_t dim_;
    ks_ompl_motion_fn fn_;
    void* user_;
};

// Benchmark only: the C++ twin of the Rust "outside a disc" closure.
class DiscChecker final : public ob::StateValidityChecker {
public:
    DiscChecker(ob::SpaceInformation* si, double cx, double cy, double r)
        : ob::StateValidityChecker(si), cx_(cx), cy_(cy), r2_(r * r) {}

    bool isValid(const ob::State* s) const override {
        const double* v = s->as<ob::RealVectorStateSpace::StateType>()->values;
        const double dx = v[0] - cx_, dy = v[1] - cy_;
        return dx * dx + dy * dy > r2_;
    }

private:
    double cx_, cy_, r2_;
};

// Uniform samples behind OMPL's informed-sampler interface.
class UniformInfSampler final : public ob::InformedSampler {
public:
    UniformInfSampler(const ob::ProblemDefinitionPtr& pdef, unsigned int max_calls)
        : ob::InformedSampler(pdef, max_calls),
          base_(pdef->getSpaceInformation()->allocStateSampler()) {}

    bool sampleUniform(ob::State* s, const ob::Cost&) override {
        base_->sampleUniform(s);
        return true;
    }
    bool sampleUniform(ob::State* s, const ob::Cost&, const ob::Cost&) override {
        base_->sampleUniform(s);
        return true;
    }
    bool hasInformedMeasure() const override { return false; }
    double getInformedMeasure(const ob::Cost&) const override { return space_->getMeasure(); }

private:
    ob::StateSamplerPtr base_;
};

// Path length, for SE(2). OMPL 1.5.2's direct informed sampler (PathLengthDirectInfSampler)
// measures only the R^2 part of SE(2) while BIT* asks for samples whose heuristic reaches a cost
// that includes the yaw part; when no state of the bounds reaches it, BIT* loops forever inside
// the sampler without polling its termination condition (fixed upstream after 1.5.2, OMPL PR
// #812). Sampling uniformly instead keeps BIT* correct, only less focused.
class Se2PathLength final : public ob::PathLengthOptimizationObjective {
public:
    using ob::PathLengthOptimizationObjective::PathLengthOptimizationObjective;

    ob::InformedSamplerPtr allocInformedStateSampler(const ob::ProblemDefinitionPtr& pdef,
                                                     unsigned int max_calls) const override {
        return std::make_shared<UniformInfSampler>(pdef, max_calls);
    }
};

template <class P>
ob::PlannerPtr with_range(const ob::SpaceInformationPtr& si, double range) {
    auto p = std::make_shared<P>(si);
    if (range > 0.0) p->setRange(range);
    return p;
}

ob::PlannerPtr make_planner(int32_t which, const ob::SpaceInformationPtr& si, double range) {
    switch (which) {
        case KS_OMPL_RRT_CONNECT: return with_range<og::RRTConnect>(si, range);
        case KS_OMPL_RRT: return with_range<og::RRT>(si, range);
        case KS_OMPL_RRT_STAR: return with_range<og::RRTstar>(si, range);
        case KS_OMPL_PRM: return std::make_shared<og::PRM>(si);
        case KS_OMPL_PRM_STAR: return std::make_shared<og::PRMstar>(si);
        case KS_OMPL_KPIECE1: return with_range<og::KPIECE1>(si, range);
        case KS_OMPL_BKPIECE1: return with_range<og::BKPIECE1>(si, range);
        case KS_OMPL_LBKPIECE1: return with_range<og::LBKPIECE1>(si, range);
        case KS_OMPL_EST: return with_range<og::EST>(si, range);
        case KS_OMPL_SBL: return with_range<og::SBL>(si, range);
        case KS_OMPL_BIT_STAR: return std::make_shared<og::BITstar>(si);
        default: throw ks::InvalidArgument("unknown planner id");
    }
}

ob::StateSpacePtr make_space(const ks_ompl_plan_request& r) {
    ob::RealVectorBounds bounds(static_cast<unsigned int>(r.bounds_len));
    for (size_t i = 0; i < r.bounds_len; ++i) {
        bounds.setLow(static_cast<unsigned int>(i), r.lower[i]);
        bounds.setHigh(static_cast<unsigned int>(i), r.upper[i]);
    }
    if (r.space == KS_OMPL_SPACE_SE2) {
        if (r.dim != 3 || r.bounds_len != 2) throw ks::InvalidArgument("SE(2) needs dim 3, 2 bounds");
        auto space = std::make_shared<ob::SE2StateSpace>();
        space->setBounds(bounds);
        return space;
    }
    if (r.space != KS_OMPL_SPACE_REAL_VECTOR) throw ks::InvalidArgument("unknown space id");
    if (r.dim != r.bounds_len) throw ks::InvalidArgument("real vector space needs dim bounds");
    auto space = std::make_shared<ob::RealVectorStateSpace>(static_cast<unsigned int>(r.dim));
    space->setBounds(bounds);
    if (r.dim <= 2) {
        // OMPL 1.5.2's default projection for dim <= 2, RealVectorIdentityProjectionEvaluator,
        // maps `copySize_` *bytes* as elements: it reads past the state and, in Debian's build
        // (Eigen assertions on), aborts the process in every projection-based planner (KPIECE
        // family, SBL). Register the equivalent orthogonal projection instead. Cell sizes are
        // set explicitly (OMPL's default: a twentieth of each side) so that StateSpace::setup
        // keeps this projection as user-configured.
        std::vector<unsigned int> axes(r.dim);
        std::vector<double> cells(r.dim);
        for (size_t i = 0; i < r.dim; ++i) {
            axes[i] = static_cast<unsigned int>(i);
            const double side = r.upper[i] - r.lower[i];
            cells[i] = side > 0.0 ? side / 20.0 : 1.0;
        }
        space->registerDefaultProjection(
            std::make_shared<ob::RealVectorOrthogonalProjectionEvaluator>(space, cells, axes));
    }
    return space;
}

void set_state(ob::ScopedState<>& st, bool se2, const double* q, size_t dim) {
    for (size_t i = 0; i < dim; ++i) st[static_cast<unsigned int>(i)] = q[i];
    // OMPL's SO(2) bounds are the half-open [-pi, pi): its bounds check rejects any other
    // representative, pi itself included (a robot facing -x: atan2(0, -1) is pi). remainder
    // maps into the closed [-pi, pi], so its pi becomes -pi, the same heading.
    if (se2) {
        double yaw = std::remainder(q[2], 2.0 * M_PI);
        if (yaw >= M_PI) yaw -= 2.0 * M_PI;
        st[2] = yaw;
    }
}

bool admissible(const ob::SpaceInformationPtr& si, const ob::ScopedState<>& st) {
    return si->satisfiesBounds(st.get()) && si->isValid(st.get());
}

}  // namespace

KS_API int ks_ompl_plan(const ks_ompl_plan_request* request, ks_ompl_validity_fn valid,
                        void* valid_user, ks_ompl_motion_fn motion, void* motion_user,
                        ks_ompl_cancel_fn cancel, void* cancel_user,
                        ks_ompl_path_sink sink, void* sink_user, ks_ompl_plan_result* out,
                        char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        if (!request || !valid || !sink || !out) throw ks::InvalidArgument("null argument");
        const ks_ompl_plan_request& r = *request;
        const bool se2 = r.space == KS_OMPL_SPACE_SE2;
        out->status = ob::PlannerStatus::UNKNOWN;
        out->planning_time_s = 0.0;
        out->simplification_time_s = 0.0;
        out->goal_distance = std::numeric_limits<double>::quiet_NaN();
        out->iterations = 0;

        // The budget starts now: space set-up and the planner's setup() count against it.
        // Capped at ~31 years: OMPL converts the budget to integer nanoseconds.
        const double budget_s = std::min(r.budget_s, 1e9);
        const Clock::time_point t0 = Clock::now();
        auto stop = ob::timedPlannerTerminationCondition(budget_s);
        auto cancelled = [cancel, cancel_user] { return cancel && cancel(cancel_user) != 0; };
        if (cancel) {
            stop = ob::plannerOrTerminationCondition(
                stop, ob::PlannerTerminationCondition([&cancelled] { return cancelled(); }));
        }
        // The planners check their condition once per iteration: counting the checks gives an
        // iteration budget that ends the search at the same point whatever the machine's load.
        std::uint64_t checks = 0;
        const std::uint64_t max_checks = r.max_iterations;
        stop = ob::plannerOrTerminationCondition(
            ob::PlannerTerminationCondition([&checks, max_checks] {
                ++checks;
                return max_checks > 0 && checks > max_checks;
            }),
            stop);

        ob::StateSpacePtr space = make_space(r);
        auto si = std::make_shared<ob::SpaceInformation>(space);
        si->setStateValidityChecker(
            std::make_shared<CallbackChecker>(si.get(), se2, r.dim, valid, valid_user));
        si->setStateValidityCheckingResolution(r.resolution);
        if (motion) {
            si->setMotionValidator(std::make_shared<CallbackMotionValidator>(si.get(), se2, r.dim,
                                                                             motion, motion_user));
        }
        si->setup();  // throws for a space of zero extent; keeps the motion validator set

        ob::ScopedState<> start(space), goal(space);
        set_state(start, se2, r.start, r.dim);
        set_state(goal, se2, r.goal, r.dim);
        if (!admissible(si, start)) {
            out->status = ob::PlannerStatus::INVALID_START;
        } else if (!admissible(si, goal)) {
            out->status = ob::PlannerStatus::INVALID_GOAL;
        }
        if (out->status != ob::PlannerStatus::UNKNOWN) {
            out->planning_time_s = seconds_since(t0);
            return;
        }

        auto pdef = std::make_shared<ob::ProblemDefinition>(si);
        pdef->setStartAndGoalStates(start, goal,
                                    std::max(r.goal_tolerance, std::numeric_limits<double>::epsilon()));
        // Without a threshold, each planner keeps its default objective (and stopping rule),
        // except BIT* in SE(2), which needs the sampler fix (its default threshold is the same).
        if (r.has_cost_threshold || (se2 && r.planner == KS_OMPL_BIT_STAR)) {
            ob::OptimizationObjectivePtr objective;
            if (se2) {
                objective = std::make_shared<Se2PathLength>(si);
            } else {
                objective = std::make_shared<ob::PathLengthOptimizationObjective>(si);
            }
            if (r.has_cost_threshold) objective->setCostThreshold(ob::Cost(r.cost_threshold));
            pdef->setOptimizationObjective(objective);
        }
        ob::PlannerPtr planner = make_planner(r.planner, si, r.range);
        planner->setProblemDefinition(pdef);
        planner->setup();
        const ob::PlannerStatus status = planner->solve(stop);
        out->status = static_cast<ob::PlannerStatus::StatusType>(status);
        out->planning_time_s = seconds_since(t0);
        out->iterations = checks;
        if (!status || !pdef->getSolutionPath()) return;

        og::PathGeometric path(*pdef->getSolutionPath()->as<og::PathGeometric>());
        const Clock::time_point t1 = Clock::now();
        if (r.simplify == KS_OMPL_SIMPLIFY_SHORTCUT && !cancelled()) {
            // Each pass only replaces pieces by motions it checked; bounded by the state count.
            og::PathSimplifier simplifier(si);
            simplifier.reduceVertices(path);
            simplifier.shortcutPath(path);
        } else if (r.simplify != KS_OMPL_SIMPLIFY_OFF && !cancelled()) {
            // No goal is given to the simplifier, so it never moves the path's last state.
            og::PathSimplifier simplifier(si);
            og::PathGeometric simplified(path);
            const double remaining = std::max(0.0, budget_s - seconds_since(t0));
            auto simplify_stop = ob::timedPlannerTerminationCondition(remaining);
            if (cancel) {
                simplify_stop = ob::plannerOrTerminationCondition(
                    simplify_stop,
                    ob::PlannerTerminationCondition([&cancelled] { return cancelled(); }));
            }
            // At least one pass even when the planner used the whole budget.
            if (simplifier.simplify(simplified, simplify_stop, true)) path = simplified;
        }
        if (r.interpolate_to > 0) path.interpolate(r.interpolate_to);
        out->simplification_time_s = seconds_since(t1);

        const size_t n = path.getStateCount();
        if (n > 0) out->goal_distance = si->distance(path.getState(n - 1), goal.get());
        std::vector<double> q(r.dim);
        for (size_t i = 0; i < n; ++i) {
            to_flat(se2, path.getState(i), r.dim, q.data());
            sink(sink_user, q.data(), r.dim);
        }
    });
}

KS_API int ks_ompl_set_seed(uint64_t seed, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        ompl::RNG::setSeed(static_cast<std::uint_fast32_t>(seed == 0 ? 1 : seed));
    });
}

KS_API int ks_ompl_set_log_level(int32_t level, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        if (level < ompl::msg::LOG_DEV2 || level > ompl::msg::LOG_NONE) {
            throw ks::InvalidArgument("log level out of range");
        }
        ompl::msg::setLogLevel(static_cast<ompl::msg::LogLevel>(level));
    });
}

KS_API int ks_ompl_bench_validity(double cx, double cy, double radius, size_t n_states,
                                  size_t passes, ks_ompl_validity_fn valid, void* valid_user,
                                  ks_ompl_bench_result* out, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        if (!valid || !out) throw ks::InvalidArgument("null argument");
        auto space = std::make_shared<ob::RealVectorStateSpace>(2);
        space->setBounds(0.0, 1.0);
        auto si_cb = std::make_shared<ob::SpaceInformation>(space);
        si_cb->setStateValidityChecker(
            std::make_shared<CallbackChecker>(si_cb.get(), false, 2, valid, valid_user));
        si_cb->setup();
        auto si_cpp = std::make_shared<ob::SpaceInformation>(space);
        si_cpp->setStateValidityChecker(std::make_shared<DiscChecker>(si_cpp.get(), cx, cy, radius));
        si_cpp->setup();

        std::vector<ob::State*> states(n_states);
        auto sampler = si_cb->allocStateSampler();
        for (auto& s : states) {
            s = si_cb->allocState();
            sampler->sampleUniform(s);
        }
        auto sweep = [&](const ob::SpaceInformationPtr& si, uint64_t& ns, uint64_t& count) {
            uint64_t valid_count = 0;
            const Clock::time_point t = Clock::now();
            for (size_t p = 0; p < passes; ++p) {
                for (const ob::State* s : states) valid_count += si->isValid(s) ? 1 : 0;
            }
            ns = static_cast<uint64_t>(
                std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t).count());
            count = passes > 0 ? valid_count / passes : 0;
        };
        sweep(si_cb, out->callback_ns, out->callback_valid);
        sweep(si_cpp, out->cpp_ns, out->cpp_valid);
        for (ob::State* s : states) si_cb->freeState(s);
    });
}
