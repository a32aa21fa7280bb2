// A check run in a child process, so that a crash, an abort (an exception
// thrown across the C boundary ends in std::terminate), an exception the check
// lets out or a hang is reported as that check's failure instead of ending
// the host or the test that called it.
#pragma once

#include <functional>
#include <string>

namespace mh::testhost {

// A check that takes longer hangs (killed, reported).
constexpr unsigned kCheckSeconds = 120;

// Runs `body` in a child: "" from it is a pass, anything else the failure.
std::string isolated(const std::function<std::string()>& body);

}  // namespace mh::testhost
