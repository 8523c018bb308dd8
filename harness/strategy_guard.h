// The wrapper the runner puts around every strategy it creates. It does two things no strategy
// should have to: it announces each phase before the strategy's code runs (so a crash or a hang in
// an isolated child is reported with the phase it was in), and it injects the project's own test
// faults (NURBSBENCH_INJECT_FAULT) into a named strategy and phase, so every strategy gets both
// without an edit.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "strategies/registry.h"

namespace nurbs {

// The phase board: the last phase announced in this process. Announcing is a store into memory
// (no system call), so it costs nothing inside timed regions.
void announce_phase(std::string_view phase);
std::string current_phase();
// Puts the board in `file` (created, MAP_SHARED), so another process reads the last phase after
// this one crashed or was killed. The measurement child calls it before running any strategy.
void share_phase_board(const std::filesystem::path& file);
// What a board file says ("" when nothing was announced).
std::string read_phase_board(const std::filesystem::path& file);

// Test-only fault injection: NURBSBENCH_INJECT_FAULT=<strategy>:<phase>:<kind>, with phase one of
// setup (the factory), prepare, evaluate, read_back, classify, render, update and kind one of crash
// (raise SIGSEGV), hang (block forever), throw (a std::runtime_error), nan (read_back's positions
// all NaN; phase read_back). Off when the variable is unset or empty.
struct InjectedFault {
  std::string strategy, phase, kind;
};
// Parsed once per process. Throws InputError naming the variable when it is malformed; the run
// and measure-child verbs call it before measuring so a typo is exit 2, not a silent no-fault run.
const std::optional<InjectedFault>& injected_fault();

// entry.create(options) behind the wrapper; announces "setup" first (the factory builds contexts
// and compiles shaders).
std::unique_ptr<Strategy> create_guarded(const StrategyEntry& entry,
                                         const StrategyOptions& options);

}  // namespace nurbs
