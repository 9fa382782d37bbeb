// Interpreter speed against Lua 5.4 (Debian lua5.4), and the parse time of a large program.
//
// 1. The same loop-heavy algorithm in VAL II and in idiomatic Lua (local variables): a CALL per
//    array element (arithmetic, by-reference result), a sieve of Eratosthenes over an array,
//    and a WHILE loop of modular arithmetic. Both print the same checksums (`agreement`).
//    Both in CPU time: VAL's Interpreter::run in thread CPU time (LOAD excluded), Lua's
//    os.clock() around the algorithm inside the script (start-up excluded). Median of kRuns
//    runs each, VAL and Lua alternated; ratio = ours / Lua. Lua is skipped (peer_us = null)
//    when `lua5.4` is not on PATH.
// 2. LOAD (parse + check) of a generated 100,000-line program (programs of 100 lines with
//    assignments, IF blocks, FOR loops and CALLs): CPU time, median of 3.
// 3. Chains of operators (issue 17): one statement `x = 0 + 1 + 1 ...`, `x = 1 == 1 == ...` and
//    `$s = "a" + "" + "" ...` of 10^4, 10^5 and 10^6 terms, LOAD and run of the one program in
//    CPU time, median of 3; us_per_term staying flat from 10^4 to 10^6 is the linear cost.
// Writes bench/results/interpreter.json (or argv[1]) and prints a table.
#include "cpu_time.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "asimov/robots/puma560.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

using namespace asimov;

namespace {

constexpr int kRuns = 11;

constexpr const char* kValProgram = R"(.PROGRAM bench()
    n = 30000
    FOR i = 1 TO n
        a[i] = (i * 7919) MOD 1000
    END
    total = 0
    FOR r = 1 TO 10
        FOR i = 1 TO n
            CALL f(a[i], r, v)
            total = total + v
        END
    END
    m = 60000
    FOR i = 2 TO m
        s[i] = 1
    END
    count = 0
    FOR i = 2 TO m
        IF s[i] THEN
            count = count + 1
            FOR j = i * i TO m STEP i
                s[j] = 0
            END
        END
    END
    x = 0
    k = 0
    WHILE k < 2000000 DO
        x = (x * 3 + k) MOD 1001
        k = k + 1
    END
    TYPE total, count, x
.END
.PROGRAM f(x, r, out)
    out = (x * r + 3) MOD 17
.END
)";

constexpr const char* kLuaProgram = R"(local function f(x, r) return (x * r + 3) % 17 end
local t0 = os.clock()
local n = 30000
local a = {}
for i = 1, n do a[i] = (i * 7919) % 1000 end
local total = 0
for r = 1, 10 do for i = 1, n do total = total + f(a[i], r) end end
local m = 60000
local s = {}
for i = 2, m do s[i] = 1 end
local count = 0
for i = 2, m do
  if s[i] ~= 0 then
    count = count + 1
    for j = i * i, m, i do s[j] = 0 end
  end
end
local x, k = 0, 0
while k < 2000000 do x = (x * 3 + k) % 1001; k = k + 1 end
local t1 = os.clock()
print(string.format("%d %d %d", total, count, x))
print(string.format("%.9f", t1 - t0))
)";

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

motion::Cell puma_cell() {
  motion::Cell cell;
  cell.robot = robots::puma560();
  cell.collision.enabled = false;
  return cell;
}

// Runs the VAL program once; its output and time [us].
std::pair<std::string, double> run_val() {
  motion::Simulator sim(puma_cell());
  std::ostringstream out;
  interpreter::Interpreter interp(sim, out);
  if (!interp.load_source(kValProgram, "bench.v2").empty()) throw std::runtime_error("bench.v2 does not load");
  const double t0 = cpu_us();
  const interpreter::RunResult r = interp.run("bench");
  const double t1 = cpu_us();
  if (r.status != interpreter::RunStatus::completed) throw std::runtime_error(interpreter::format_diagnostic(r.error));
  std::string text = out.str();
  if (!text.empty() && text.back() == '\n') text.pop_back();
  return {text, t1 - t0};
}

// Runs the Lua program once; its output and time [us], or nullopt without lua5.4.
std::optional<std::pair<std::string, double>> run_lua(const std::filesystem::path& script) {
  FILE* p = popen(("lua5.4 '" + script.string() + "' 2>/dev/null").c_str(), "r");
  if (!p) return std::nullopt;
  char line[256];
  std::vector<std::string> lines;
  while (std::fgets(line, sizeof line, p)) {
    std::string s = line;
    if (!s.empty() && s.back() == '\n') s.pop_back();
    lines.push_back(s);
  }
  if (pclose(p) != 0 || lines.size() != 2) return std::nullopt;
  return std::make_pair(lines[0], std::stod(lines[1]) * 1e6);
}

// A generated program of `lines` lines: programs of 100 lines each.
std::string generated_source(int lines) {
  std::string src;
  src.reserve(static_cast<std::size_t>(lines) * 32);
  const int programs = lines / 100;
  for (int p = 0; p < programs; ++p) {
    src += fmt::format(".PROGRAM gen{}(a, b, $s)\n", p);
    src += "    AUTO i, t\n";
    int used = 2;
    int k = 0;
    while (used < 98) {
      switch (k++ % 4) {
        case 0: src += fmt::format("    t = (a + {}) * b - {} MOD 7\n", k, k); used += 1; break;
        case 1: src += fmt::format("    IF t > {} AND a <> b THEN\n        $s = $s + \"x{}\"\n    END\n", k, k); used += 3; break;
        case 2: src += fmt::format("    FOR i = 1 TO {}\n        v[i] = SQRT(i * {}) + SIN(t)\n    END\n", k, k); used += 3; break;
        default: src += fmt::format("    CALL gen{}(t, {}, $s)\n", (p + 1) % programs, k); used += 1; break;
      }
    }
    while (used < 99) { src += "    ; filler\n"; ++used; }
    src += ".END\n";
  }
  return src;
}

struct ChainRow {
  std::string kind;
  int terms;
  double load_us, run_us;
};

// LOAD and run of `.PROGRAM chain()` holding `head` followed by `terms - 1` times `step`.
ChainRow chain_row(const std::string& kind, const std::string& head, const std::string& step, int terms) {
  std::string src = ".PROGRAM chain()\n    " + head;
  src.reserve(src.size() + step.size() * static_cast<std::size_t>(terms) + 16);
  for (int i = 1; i < terms; ++i) src += step;
  src += "\n.END\n";
  std::vector<double> load, run;
  for (int k = 0; k < 3; ++k) {
    motion::Simulator sim(puma_cell());
    std::ostringstream out;
    interpreter::Interpreter interp(sim, out);
    const double t0 = cpu_us();
    if (!interp.load_source(src, "chain.v2").empty()) throw std::runtime_error("chain.v2 does not load: " + kind);
    const double t1 = cpu_us();
    const interpreter::RunResult r = interp.run("chain");
    const double t2 = cpu_us();
    if (r.status != interpreter::RunStatus::completed) throw std::runtime_error(interpreter::format_diagnostic(r.error));
    load.push_back(t1 - t0);
    run.push_back(t2 - t1);
  }
  return {kind, terms, median(load), median(run)};
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path out_path = argc > 1 ? std::filesystem::path(argv[1])
      : std::filesystem::path(__FILE__).parent_path() / "results" / "interpreter.json";

  // 1. VAL against Lua.
  std::vector<double> ours, peer;
  std::string ours_text, peer_text;
  const auto script = std::filesystem::temp_directory_path() / "asimov_bench_interpreter.lua";
  std::ofstream(script) << kLuaProgram;
  bool have_lua = true;
  for (int i = 0; i < kRuns; ++i) {  // alternated, so that both see the same machine load
    auto [text, us] = run_val();
    ours_text = text;
    ours.push_back(us);
    if (!have_lua) continue;
    if (auto r = run_lua(script)) {
      peer_text = r->first;
      peer.push_back(r->second);
    } else {
      have_lua = false;
    }
  }
  std::filesystem::remove(script);
  const double ours_us = median(ours);
  const double worst_us = *std::max_element(ours.begin(), ours.end());

  // 2. LOAD of a generated 100,000-line program.
  const std::string source = generated_source(100'000);
  const long line_count = std::count(source.begin(), source.end(), '\n');
  std::vector<double> parse;
  for (int i = 0; i < 3; ++i) {
    motion::Simulator sim(puma_cell());
    std::ostringstream out;
    interpreter::Interpreter interp(sim, out);
    const double t0 = cpu_us();
    const auto diags = interp.load_source(source, "generated.v2");
    const double t1 = cpu_us();
    for (const auto& d : diags)
      if (!d.warning) {
        std::cerr << interpreter::format_diagnostic(d);
        return 1;
      }
    parse.push_back(t1 - t0);
  }
  const double parse_us = median(parse);

  // 3. Chains of 10^4, 10^5, 10^6 terms.
  std::vector<ChainRow> chains;
  for (int terms : {10'000, 100'000, 1'000'000}) {
    chains.push_back(chain_row("x = 0 + 1 + 1 ...", "x = 0", " + 1", terms));
    chains.push_back(chain_row("x = 1 == 1 == ...", "x = 1", " == 1", terms));
    chains.push_back(chain_row("$s = \"a\" + \"\" + ...", "$s = \"a\"", " + \"\"", terms));
  }

  std::string json = "[\n";
  if (have_lua) {
    const double peer_us = median(peer);
    json += fmt::format(R"J(  {{"name": "loop-heavy program (CALL per element, sieve, WHILE arithmetic)", "ours_us": {:.1f}, "ours_worst_us": {:.1f}, "peer": "Lua 5.4 (lua5.4, locals)", "peer_us": {:.1f}, "ratio": {:.3f}, "agreement": {}, "runs": {}}},)J",
                        ours_us, worst_us, peer_us, ours_us / peer_us, ours_text == peer_text ? 1 : 0, kRuns);
    std::printf("VAL %.1f ms (worst %.1f), Lua 5.4 %.1f ms: ratio %.2f, checksums %s (%s)\n", ours_us / 1e3,
                worst_us / 1e3, peer_us / 1e3, ours_us / peer_us, ours_text == peer_text ? "agree" : "DIFFER",
                ours_text.c_str());
  } else {
    json += fmt::format(R"J(  {{"name": "loop-heavy program (CALL per element, sieve, WHILE arithmetic)", "ours_us": {:.1f}, "ours_worst_us": {:.1f}, "peer": "Lua 5.4 (not installed)", "peer_us": null, "ratio": null, "agreement": null, "runs": {}}},)J",
                        ours_us, worst_us, kRuns);
    std::printf("VAL %.1f ms (worst %.1f); lua5.4 not found: no ratio\n", ours_us / 1e3, worst_us / 1e3);
  }
  json += "\n";
  json += fmt::format(R"J(  {{"name": "LOAD (parse + check) of a generated {}-line program", "ours_us": {:.1f}, "ours_worst_us": {:.1f}, "lines": {}, "us_per_line": {:.3f}, "runs": 3}})J",
                      line_count, parse_us, *std::max_element(parse.begin(), parse.end()), line_count, parse_us / static_cast<double>(line_count));
  std::printf("LOAD of %ld lines: %.1f ms (%.2f us/line)\n", line_count, parse_us / 1e3, parse_us / static_cast<double>(line_count));
  for (const ChainRow& c : chains) {
    const double per_term = (c.load_us + c.run_us) / c.terms;
    std::string kind;  // the statement, as a JSON string
    for (char ch : c.kind) kind += ch == '"' ? std::string("\\\"") : std::string(1, ch);
    json += fmt::format(",\n  {{\"name\": \"one statement {} of {} terms (LOAD + run)\", \"terms\": {}, \"load_us\": {:.1f}, \"run_us\": {:.1f}, \"us_per_term\": {:.3f}, \"runs\": 3}}",
                        kind, c.terms, c.terms, c.load_us, c.run_us, per_term);
    std::printf("chain %-24s %8d terms: LOAD %8.1f ms, run %7.1f ms (%.3f us/term)\n", c.kind.c_str(), c.terms, c.load_us / 1e3,
                c.run_us / 1e3, per_term);
  }
  json += "\n]\n";
  std::ofstream(out_path) << json;
  std::printf("wrote %s\n", out_path.string().c_str());
  return 0;
}
