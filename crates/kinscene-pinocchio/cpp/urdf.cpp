// kinscene Pinocchio shim: URDF parsing (Pinocchio's urdfdom-based parser).
//
// urdfdom reports why a document is rejected through console_bridge (printed to stderr by
// default) and Pinocchio then throws a generic "does not contain a valid URDF model". The
// parse below runs with a console_bridge handler that collects those diagnostics, so they reach
// the caller in the exception message instead of the terminal. console_bridge's handler is
// process-global, hence the mutex: URDF parses are serialised (they are rare and fast).
#include "urdf.hpp"

#include <mutex>
#include <stdexcept>
#include <string>

#include <console_bridge/console.h>
#include <pinocchio/multibody.hpp>
#include <pinocchio/parsers/urdf.hpp>

namespace {

class Collect final : public console_bridge::OutputHandler {
public:
    void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
        if (level < console_bridge::CONSOLE_BRIDGE_LOG_WARN) return;
        if (!messages.empty()) messages += "; ";
        messages += text;
    }
    std::string messages;
};

std::mutex parse_mutex;

}  // namespace

pinocchio::Model ks::model_from_urdf(const std::string& xml) {
    const std::lock_guard<std::mutex> lock(parse_mutex);
    Collect collect;
    console_bridge::useOutputHandler(&collect);
    struct Restore {
        ~Restore() { console_bridge::restorePreviousOutputHandler(); }
    } restore;
    pinocchio::Model model;
    try {
        pinocchio::urdf::buildModelFromXML(xml, model);
    } catch (const std::exception& e) {
        std::string message = e.what();
        if (!collect.messages.empty()) message += " (urdfdom: " + collect.messages + ")";
        throw std::runtime_error(message);
    }
    return model;
}
