// Evaluator plugins: a shared library implementing include/nurbsbench/evaluator.h, loaded with
// `--plugin PATH`, becomes one more strategy (role "plugin") behind the Strategy interface, so the
// runner, isolation, scoring and gates treat it as any built-in one.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "harness/isolation.h"
#include "strategies/registry.h"

namespace nurbs {

// Adds the strategy `path` holds (strategies/registry.h add_strategy). No code of the library runs
// in this process: it is probed -- dlopen (its constructors), the entry point, the table, its name
// and capabilities -- in a child of the measurement server, under `isolation`'s watchdog (at most
// 60 s) and memory limit, and what the child answers becomes the entry. Every measurement loads it
// again in the child that measures it (or, under --isolation none, at the first create() in this
// process). A library that cannot be used -- it fails to load, crashes, hangs or exits while
// probed, lacks the entry point or a required function, has an unsupported ABI version or
// struct_size, or an invalid name -- is still added, under its file name without "lib" and ".so"
// held to the name rule (libbroken.so -> "broken", "My Plugin!.so" -> "my-plugin-"), and every
// measurement of it fails with that one-line reason (plugin_problem): a broken plugin is a result,
// like a crashing one. Throws InputError (exit 2) when the path is not a readable regular file or
// the name is already a strategy's (built in or another plugin).
const StrategyEntry& load_plugin(const std::filesystem::path& path,
                                 const IsolationSettings& isolation = {});
void load_plugins(const std::vector<std::string>& paths, const IsolationSettings& isolation = {});

// The measurement child's load: opens the library in this process (which is isolated already).
const StrategyEntry& load_plugin_in_process(const std::filesystem::path& path);

// Why an added plugin cannot be used ("plugin PATH: <what>"); nullopt for a usable one and for
// every built-in strategy.
std::optional<std::string> plugin_problem(const StrategyEntry& entry);

// The probe, in the isolated child: loads DIR/library (its path) and writes DIR/probe.json (the
// problem, or the name, version, description and capabilities). Exit code 0 when it answered.
int probe_plugin_child(const std::filesystem::path& directory);

// Bytes a plugin handed us (a message, a name, a description), fit for JSON, CSV and a terminal:
// valid UTF-8 (each invalid sequence becomes U+FFFD), control characters escaped (\n, \t, \xNN,
// \u0085), cut after `max_bytes` with "...".
std::string plugin_text(std::string_view bytes, std::size_t max_bytes = 512);

// SHA-256 of the file's bytes, lowercase hex. Throws std::runtime_error when it cannot be read.
std::string file_sha256(const std::filesystem::path& path);

}  // namespace nurbs
