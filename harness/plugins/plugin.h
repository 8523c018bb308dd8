// Evaluator plugins (issue 31): a shared library implementing include/nurbsbench/evaluator.h,
// loaded with `--plugin PATH`, becomes one more strategy (role "plugin") behind the Strategy
// interface, so the runner, isolation, scoring and gates treat it as any built-in one.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "strategies/registry.h"

namespace nurbs {

// Loads `path` and adds its strategy (strategies/registry.h add_strategy). The library is
// dlopen'ed in this process to read its identity and capabilities; every measurement of it that
// `run` and `recommend` isolate loads it again in the child that measures. A library that cannot
// be used -- it fails to load, lacks the entry point or a required function, has an unsupported
// ABI version or an invalid name -- is still added, under its file name without "lib" and ".so"
// (libbroken.so -> "broken"), and every measurement of it fails with that one-line reason: a
// broken plugin is a result, like a crashing one. Throws InputError (exit 2) when the name is
// already a strategy's (built in or another plugin). The handle is never closed: the entry's
// functions point into it.
const StrategyEntry& load_plugin(const std::filesystem::path& path);
void load_plugins(const std::vector<std::string>& paths);

// SHA-256 of the file's bytes, lowercase hex. Throws std::runtime_error when it cannot be read.
std::string file_sha256(const std::filesystem::path& path);

}  // namespace nurbs
