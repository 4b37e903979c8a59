// Small node types that exercise the evaluator: numbers, sums, failures,
// file writes, cancellation. Each compute also bumps a global counter per
// type so tests can count recomputations from outside.
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"

using namespace geobrush;

namespace {

void number(Context& ctx) {
  ctx.out("value", std::make_shared<Scalar>(ctx.param<double>("value")));
}

void add(Context& ctx) {
  double sum = ctx.in<Scalar>("a")->value;
  if (ctx.hasInput("b")) sum += ctx.in<Scalar>("b")->value;
  ctx.out("value", std::make_shared<Scalar>(sum));
}

// in * gain + the square of `in`, the square derived once per input value by the framework.
void derivedSquare(Context& ctx) {
  const auto in = ctx.in<Scalar>("in");
  const auto square = ctx.derived("square", {"in"}, 0,
                                  [&] { return std::make_shared<double>(in->value * in->value); });
  ctx.out("value", std::make_shared<Scalar>(in->value * ctx.param<double>("gain") + *square));
}

// in * gain, built in a retired value of its own made from an equal input where there is one.
struct MadeFrom {
  Hash in = 0;
};
void recyclingScale(Context& ctx) {
  const Hash in = ctx.inputKeyOf("in");
  auto value =
      ctx.recycle<Scalar, MadeFrom>("value", [&](const MadeFrom& made) { return made.in == in; })
          .value;
  if (!value) value = std::make_shared<Scalar>(0.0);
  value->value = ctx.in<Scalar>("in")->value * ctx.param<double>("gain");
  ctx.outRecyclable("value", value, std::make_shared<const MadeFrom>(MadeFrom{in}));
}

void fail(Context& ctx) {
  const std::string how = ctx.param<std::string>("how");
  if (how == "node_error") throw NodeError::param("how", "asked to fail");
  if (how == "std_exception") throw std::runtime_error("a std::exception from the node");
  if (how == "unknown") throw 42;
  if (how == "no_output") return;
  if (how == "wrong_type") {
    ctx.out("value", std::make_shared<Metrics>());
    return;
  }
  ctx.out("value", std::make_shared<Scalar>(ctx.in<Scalar>("in")->value));
}

void writeText(Context& ctx) {
  const double value = ctx.in<Scalar>("value")->value;
  ctx.writeFile(ctx.path("path"), [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp);
    out << value << "\n";
  });
}

void readText(Context& ctx) {
  std::ifstream in(ctx.path("path"));
  double value = 0;
  if (!(in >> value)) throw NodeError::param("path", "cannot read " + ctx.path("path").string());
  ctx.out("value", std::make_shared<Scalar>(value));
}

void slow(Context& ctx) {
  for (int i = 0; i < 1000; ++i) {
    ctx.throwIfCancelled();
    ctx.progress(i / 1000.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ctx.out("value", std::make_shared<Scalar>(ctx.in<Scalar>("in")->value));
}

// Stands in for a warm-started solver: every compute after the first starts from the previous
// one and lands a little off the exact answer, as an iteration stopped at its tolerance does.
class WarmStarted final : public Node {
 public:
  void compute(Context& ctx) override {
    usedHistory_ = computedBefore_;
    const double offset = computedBefore_ ? 1e-9 : 0.0;
    ctx.out("value", std::make_shared<Scalar>(ctx.in<Scalar>("in")->value + offset));
    computedBefore_ = true;
  }
  bool usedHistory() const override { return usedHistory_; }

 private:
  bool computedBefore_ = false;
  bool usedHistory_ = false;
};

// The last value a test.prepared_add prepared from, for test.await_prepared to wait for.
std::atomic<double> lastPrepared{std::nan("")};

// Adds a and b, having read a in prepare(): the evaluator runs that ahead, while b is computed.
class PreparedAdd final : public Node {
 public:
  void prepare(Context& ctx) override {
    prepared_.reset();
    const double a = ctx.in<Scalar>("a")->value;
    if (ctx.param<std::string>("how") == "fail_in_prepare")
      throw NodeError::input("a", "refused while preparing");
    if (ctx.param<std::string>("how") == "output_in_prepare")
      ctx.out("value", std::make_shared<Scalar>(a));
    ctx.warn("prepared from " + std::to_string(a));
    prepared_ = a;
    lastPrepared = a;
  }
  void compute(Context& ctx) override {
    if (!prepared_) throw NodeError("computed without being prepared");
    ctx.out("value", std::make_shared<Scalar>(*prepared_ + ctx.in<Scalar>("b")->value));
  }

 private:
  std::optional<double> prepared_;
};

// Passes its input through where a test.prepared_add prepared from `token` within two seconds of
// this compute's start, else outputs -1000.
void awaitPrepared(Context& ctx) {
  const double token = ctx.param<double>("token");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (lastPrepared.load() != token && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const bool seen = lastPrepared.load() == token;
  ctx.out("value", std::make_shared<Scalar>(seen ? ctx.in<Scalar>("in")->value : -1000.0));
}

// How many test.rendezvous computes have arrived, per meeting.
std::mutex meetingsMutex;
std::map<std::string, int> meetings;

// Outputs 1 once `expected` computes of its meeting have arrived within two seconds of its own
// arrival, else 0: computes that run one at a time never meet.
void rendezvous(Context& ctx) {
  const std::string meeting = ctx.param<std::string>("meeting");
  const int expected = ctx.param<int>("expected");
  {
    const std::lock_guard lock(meetingsMutex);
    ++meetings[meeting];
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  bool met = false;
  while (!met && std::chrono::steady_clock::now() < deadline) {
    {
      const std::lock_guard lock(meetingsMutex);
      met = meetings[meeting] >= expected;
    }
    if (!met) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ctx.out("value", std::make_shared<Scalar>(met ? 1.0 : 0.0));
}

void registerNodes(PluginRegistrar& r) {
  r.add(NodeTypeBuilder("test.rendezvous", 1)
            .doc("Outputs 1 where the computes of its meeting overlap in time, else 0.")
            .output<Scalar>("value", "1 where they met.")
            .paramString("meeting", "", "The meeting's name.")
            .paramInt("expected", 2, "How many computes meet.")
            .range(1, 64)
            .paramInt("seat", 0, "Tells the nodes of a meeting apart; changes nothing.")
            .compute(rendezvous)
            .build());
  r.add(NodeTypeBuilder("test.prepared_add", 1)
            .doc("Adds two scalars, reading the first in prepare().")
            .input<Scalar>("a", "First term, read in prepare().")
            .input<Scalar>("b", "Second term.")
            .output<Scalar>("value", "The sum.")
            .paramEnum("how", "none", {"none", "fail_in_prepare", "output_in_prepare"},
                       "How prepare() misbehaves.")
            .prepares({"a"})
            .node<PreparedAdd>()
            .build());
  r.add(NodeTypeBuilder("test.await_prepared", 1)
            .doc("Passes its input through once a test.prepared_add prepared from the token.")
            .input<Scalar>("in", "Passed through.")
            .output<Scalar>("value", "The input, or -1000 when nothing was prepared in time.")
            .paramDouble("token", 0.0, "The value to wait for.")
            .range(-1e9, 1e9)
            .compute(awaitPrepared)
            .build());
  r.add(NodeTypeBuilder("test.number", 1)
            .doc("Outputs its parameter as a scalar.")
            .output<Scalar>("value", "The number.")
            .paramDouble("value", 1.0, "The number to output.")
            .range(-1e9, 1e9)
            .paramString("label", "", "An unrelated label; changes nothing.")
            .compute(number)
            .build());
  r.add(NodeTypeBuilder("test.add", 2)
            .doc("Adds two scalars.")
            .input<Scalar>("a", "First term.")
            .optionalInput<Scalar>("b", "Second term (0 if unconnected).")
            .output<Scalar>("value", "The sum.")
            .paramInt("unused", 0, "Has no effect.")
            .compute(add)
            // Version 1 called the unused parameter "spare".
            .upgrade(1,
                     [](ParamMap& params) {
                       if (auto it = params.find("spare"); it != params.end()) {
                         params["unused"] = it->second;
                         params.erase(it);
                       }
                     })
            .build());
  r.add(
      NodeTypeBuilder("test.fail", 1)
          .doc("Fails in the way its parameter says, or passes its input through.")
          .input<Scalar>("in", "Passed through.")
          .output<Scalar>("value", "The input.")
          .paramEnum("how", "none",
                     {"none", "node_error", "std_exception", "unknown", "no_output", "wrong_type"},
                     "How to fail.")
          .compute(fail)
          .build());
  r.add(NodeTypeBuilder("test.write_text", 1)
            .doc("Writes its input as text.")
            .input<Scalar>("value", "The number to write.")
            .paramOutputPath("path", "value.txt", "Text file to write.")
            .compute(writeText)
            .build());
  r.add(NodeTypeBuilder("test.metric_count", 1)
            .doc("Counts the values of a metrics input.")
            .input<Metrics>("metrics", "Any metrics.")
            .output<Scalar>("value", "How many values it holds.")
            .compute([](Context& ctx) {
              const double count = double(ctx.in<Metrics>("metrics")->values.size());
              ctx.out("value", std::make_shared<Scalar>(count));
            })
            .build());
  r.add(NodeTypeBuilder("test.read_text", 1)
            .doc("Reads a number from a text file.")
            .output<Scalar>("value", "The number.")
            .paramInputPath("path", "Text file holding one number.")
            .compute(readText)
            .build());
  r.add(NodeTypeBuilder("test.derived_square", 1)
            .doc("Adds the square of its input, derived once per input value, to in * gain.")
            .input<Scalar>("in", "x")
            .output<Scalar>("value", "x gain + x^2")
            .paramDouble("gain", 1.0, "gain")
            .compute(derivedSquare)
            .build());
  r.add(NodeTypeBuilder("test.recycling_scale", 1)
            .doc("Scales its input, in a value it published before where the framework hands one "
                 "back.")
            .input<Scalar>("in", "x")
            .output<Scalar>("value", "x gain")
            .paramDouble("gain", 1.0, "gain")
            .compute(recyclingScale)
            .build());
  r.add(NodeTypeBuilder("test.warm", 1)
            .doc("Passes its input through, off by 1e-9 when warm-started from a previous compute.")
            .input<Scalar>("in", "Passed through.")
            .output<Scalar>("value", "The input (exactly, when computed cold).")
            .node<WarmStarted>()
            .build());
  r.add(NodeTypeBuilder("test.slow", 1)
            .doc("Takes a second, checking for cancellation.")
            .input<Scalar>("in", "Passed through.")
            .output<Scalar>("value", "The input.")
            .compute(slow)
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
