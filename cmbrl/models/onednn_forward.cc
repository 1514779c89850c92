#include "cmbrl/models/onednn_forward.h"

#include <torch/torch.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <mutex>
#include <new>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/core/cpu_features.h"
#include "cmbrl/core/parallel.h"

#ifdef CMBRL_HAVE_ONEDNN
#include "cmbrl/models/onednn_common.h"
#endif

namespace cmbrl {

bool OnednnForwardAvailable(bool bf16, std::string* why_not) {
#ifdef CMBRL_HAVE_ONEDNN
  // oneDNN 2.6 has bf16 products only from AVX-512 on (emulated without AVX512-BF16).
  if (bf16 && !CpuHasAvx512()) {
    if (why_not != nullptr) *why_not = "oneDNN's bf16 products need AVX-512, which this CPU lacks";
    return false;
  }
  return true;
#else
  (void)bf16;
  if (why_not != nullptr) *why_not = "this build has no oneDNN (CMBRL_WITH_ONEDNN was off)";
  return false;
#endif
}

std::string OnednnVersion() {
#ifdef CMBRL_HAVE_ONEDNN
  const dnnl_version_t* version = dnnl_version();
  return std::to_string(version->major) + "." + std::to_string(version->minor) + "." +
         std::to_string(version->patch);
#else
  return "";
#endif
}

// Rows per task of a prediction: large enough for a single-threaded product to run at speed,
// small enough that the planner's batches (a few hundred rows per member) give every core work.
// Without AVX-512, oneDNN 2.6's fp32 kernels (gemm:jit) run products of fewer than 384 rows at
// about half speed once a layer's weights outgrow the L2 cache (1024 wide: 40 against 75-80
// GFLOP/s on a Zen 3 core), so blocks are 512 rows there; the AVX-512 kernels run 256 rows at
// speed (docs/PERFORMANCE.md, v0.8.1).
std::int64_t OnednnPredictionBlockRows() {
  static const std::int64_t rows = CpuHasAvx512() ? 256 : 512;
  return rows;
}

#ifdef CMBRL_HAVE_ONEDNN

namespace {

using dnnl::memory;
using Dims = memory::dims;
using onednn::ScopedOmpThreads;

// float32 -> bfloat16, rounding to nearest even (NaN stays a NaN).
std::uint16_t ToBf16(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  if ((bits & 0x7fffffffu) > 0x7f800000u) return static_cast<std::uint16_t>((bits >> 16) | 0x40u);
  bits += 0x7fffu + ((bits >> 16) & 1u);
  return static_cast<std::uint16_t>(bits >> 16);
}

// Uninitialised bytes starting on a 64-byte boundary (a cache line, an AVX-512 register).
class CacheAlignedBytes {
 public:
  explicit CacheAlignedBytes(std::size_t size)
      : bytes_(static_cast<std::uint8_t*>(::operator new(size, kAlignment))) {}
  ~CacheAlignedBytes() { ::operator delete(bytes_, kAlignment); }
  CacheAlignedBytes(const CacheAlignedBytes&) = delete;
  CacheAlignedBytes& operator=(const CacheAlignedBytes&) = delete;
  std::uint8_t* get() const { return bytes_; }

 private:
  static constexpr std::align_val_t kAlignment{64};
  std::uint8_t* bytes_;
};

// Below this many multiply-adds a call stays on the calling thread.
constexpr std::int64_t kParallelMultiplyAdds = std::int64_t{1} << 20;

}  // namespace

struct OnednnEnsembleForward::Impl {
  struct Layer {
    std::int64_t in = 0, out = 0;
    torch::Tensor weight;  // (E, in, out) float32, contiguous; the last with the output folded in
    torch::Tensor bias;    // (E, 1, out) float32, contiguous
  };
  // Everything made for one batch size N: a primitive per layer, shared by the members (2D
  // products: oneDNN 2.6 has no fast kernel for a per-member bias on a batched product, and
  // falls back to its reference one), and each member's weights in the primitive's layout.
  struct Plan {
    std::vector<dnnl::matmul> primitives;
    std::vector<std::vector<memory>> weights;  // [layer][member]
    std::vector<memory::desc> sources, destinations, biases;
    std::size_t scratchpad_bytes = 0;
  };

  dnnl::engine engine{dnnl::engine::kind::cpu, 0};
  std::vector<Layer> layers;
  std::vector<float> input_mean, input_std;
  std::int64_t members = 0, state_dim = 0, action_dim = 0;
  bool predict_delta = false;
  mutable std::mutex plans_mutex;
  mutable std::map<std::int64_t, std::shared_ptr<const Plan>> plans;

  std::shared_ptr<const Plan> PlanFor(std::int64_t rows, bool bf16) const;

  // Writes `count` normalised [state, action] rows (the states `s`, the actions `a`) to `out`,
  // each value through `convert` into the first product's type (float, or bfloat16's bits).
  template <typename T, typename Convert>
  void NormalizedInputs(T* out, const float* s, const float* a, std::int64_t count,
                        Convert convert) const {
    const float* mean = input_mean.data();
    const float* std = input_std.data();
    const std::int64_t width = state_dim + action_dim;
    for (std::int64_t r = 0; r < count; ++r) {
      T* row = out + r * width;
      const float* state = s + r * state_dim;
      const float* action = a + r * action_dim;
      for (std::int64_t j = 0; j < state_dim; ++j) {
        row[j] = convert((state[j] - mean[j]) / std[j]);
      }
      for (std::int64_t j = 0; j < action_dim; ++j) {
        row[state_dim + j] = convert((action[j] - mean[state_dim + j]) / std[state_dim + j]);
      }
    }
  }

  // Member m's products of `plan` over the rows in `ping`, alternating with `pong`, the last
  // one written to `destination`.
  void RunLayers(const Plan& plan, std::int64_t m, std::uint8_t* ping, std::uint8_t* pong,
                 float* destination, const memory& scratch, dnnl::stream& stream) const {
    std::uint8_t* source = ping;
    std::uint8_t* spare = pong;
    for (std::size_t l = 0; l < layers.size(); ++l) {
      const bool last = l + 1 == layers.size();
      void* out = last ? static_cast<void*>(destination) : spare;
      const memory src(plan.sources[l], engine, source);
      const memory dst(plan.destinations[l], engine, out);
      const Layer& layer = layers[l];
      const memory bias(plan.biases[l], engine, layer.bias.data_ptr<float>() + m * layer.out);
      plan.primitives[l].execute(stream, {{DNNL_ARG_SRC, src},
                                          {DNNL_ARG_WEIGHTS, plan.weights[l][m]},
                                          {DNNL_ARG_BIAS, bias},
                                          {DNNL_ARG_DST, dst},
                                          {DNNL_ARG_SCRATCHPAD, scratch}});
      std::swap(source, spare);
    }
    stream.wait();
  }
};

std::shared_ptr<const OnednnEnsembleForward::Impl::Plan> OnednnEnsembleForward::Impl::PlanFor(
    std::int64_t rows, bool bf16) const {
  const std::lock_guard<std::mutex> lock(plans_mutex);
  if (auto found = plans.find(rows); found != plans.end()) return found->second;
  // Made single-threaded, as every call runs: a primitive may fix its blocking by the count.
  const ScopedOmpThreads one_thread(1);
  auto plan = std::make_shared<Plan>();
  const memory::data_type hidden = bf16 ? memory::data_type::bf16 : memory::data_type::f32;
  dnnl::stream stream(engine);
  for (std::size_t l = 0; l < layers.size(); ++l) {
    const Layer& layer = layers[l];
    const bool last = l + 1 == layers.size();
    const memory::desc source({rows, layer.in}, hidden, memory::format_tag::ab);
    const memory::desc weights({layer.in, layer.out}, hidden, memory::format_tag::any);
    const memory::desc bias({1, layer.out}, memory::data_type::f32, memory::format_tag::ab);
    const memory::desc destination({rows, layer.out}, last ? memory::data_type::f32 : hidden,
                                   memory::format_tag::ab);
    dnnl::post_ops post;
    if (!last) post.append_eltwise(1.0f, dnnl::algorithm::eltwise_relu, 0.0f, 0.0f);
    if (last && predict_delta) post.append_sum(1.0f);  // the output buffer holds the states
    dnnl::primitive_attr attributes;
    attributes.set_post_ops(post);
    attributes.set_scratchpad_mode(dnnl::scratchpad_mode::user);  // per call: thread-safe
    const dnnl::matmul::primitive_desc description(
        dnnl::matmul::desc(source, weights, bias, destination), attributes, engine);
    // Each member's weights, once, in the layout and type this primitive reads.
    std::vector<memory> member_weights;
    for (std::int64_t m = 0; m < members; ++m) {
      memory plain({{layer.in, layer.out}, memory::data_type::f32, memory::format_tag::ab}, engine,
                   layer.weight[m].data_ptr<float>());
      memory reordered(description.weights_desc(), engine);
      dnnl::reorder(plain, reordered).execute(stream, plain, reordered);
      member_weights.push_back(reordered);
    }
    plan->primitives.emplace_back(description);
    plan->weights.push_back(std::move(member_weights));
    plan->sources.push_back(source);
    plan->destinations.push_back(destination);
    plan->biases.push_back(bias);
    plan->scratchpad_bytes = std::max(plan->scratchpad_bytes,
                                      description.scratchpad_desc().get_size());
  }
  stream.wait();
  plans.emplace(rows, plan);
  return plan;
}

OnednnEnsembleForward::OnednnEnsembleForward(bool bf16) : bf16_(bf16) {
  std::string why_not;
  Require(OnednnForwardAvailable(bf16, &why_not), "the oneDNN prediction backend is not available: {}",
          why_not);
  impl_ = std::make_unique<Impl>();
}

OnednnEnsembleForward::~OnednnEnsembleForward() = default;

void OnednnEnsembleForward::SetWeights(const std::vector<torch::Tensor>& weights,
                                       const std::vector<torch::Tensor>& biases,
                                       const torch::Tensor& input_mean,
                                       const torch::Tensor& input_std,
                                       const torch::Tensor& target_mean,
                                       const torch::Tensor& target_std, bool predict_delta) {
  const torch::NoGradGuard no_grad;
  Require(!weights.empty() && weights.size() == biases.size(),
          "oneDNN backend: {} weight and {} bias tensors", weights.size(), biases.size());
  Impl& impl = *impl_;
  const std::lock_guard<std::mutex> lock(impl.plans_mutex);
  impl.plans.clear();
  impl.layers.clear();
  const auto cpu_float = [](const torch::Tensor& t) {
    return t.detach().to(torch::kCPU, torch::kFloat).contiguous();
  };
  for (std::size_t l = 0; l < weights.size(); ++l) {
    Impl::Layer layer;
    layer.weight = cpu_float(weights[l]).clone();
    layer.bias = cpu_float(biases[l]).clone();
    layer.in = layer.weight.size(1);
    layer.out = layer.weight.size(2);
    impl.layers.push_back(std::move(layer));
  }
  // Denormalisation folded into the last layer: (h W + b) * std + mean = h (W std) + (b std + m).
  Impl::Layer& last = impl.layers.back();
  const torch::Tensor scale = cpu_float(target_std).view({1, 1, -1});
  last.weight = (last.weight * scale).contiguous();
  last.bias = (last.bias * scale + cpu_float(target_mean).view({1, 1, -1})).contiguous();
  const torch::Tensor mean = cpu_float(input_mean), std = cpu_float(input_std);
  impl.input_mean.assign(mean.data_ptr<float>(), mean.data_ptr<float>() + mean.numel());
  impl.input_std.assign(std.data_ptr<float>(), std.data_ptr<float>() + std.numel());
  impl.members = impl.layers.front().weight.size(0);
  impl.state_dim = last.out;
  impl.action_dim = impl.layers.front().in - impl.state_dim;
  impl.predict_delta = predict_delta;
}

torch::Tensor OnednnEnsembleForward::Predict(const torch::Tensor& states_in,
                                             const torch::Tensor& actions_in) const {
  const Impl& impl = *impl_;
  Require(!impl.layers.empty(), "oneDNN backend: Predict before SetWeights");
  const torch::Tensor states = states_in.contiguous();
  const torch::Tensor actions = actions_in.contiguous();
  const std::int64_t members = impl.members, rows = states.size(1);
  const std::int64_t s_dim = impl.state_dim, a_dim = impl.action_dim, width = s_dim + a_dim;
  // With predict_delta the last product's sum post-op adds its output onto the states.
  torch::Tensor next =
      impl.predict_delta ? states.clone() : torch::empty({members, rows, s_dim}, torch::kFloat);
  if (rows == 0) return next;

  // The work is cut into (member, block of rows) tasks of fixed shape, each one single-threaded
  // product chain, so that a prediction's bits depend on neither the thread count nor the
  // calling thread. The last block of a member may be shorter and has a primitive of its own.
  const std::int64_t block = std::min(rows, OnednnPredictionBlockRows());
  const std::int64_t full_blocks = rows / block, tail = rows % block;
  const std::int64_t blocks = full_blocks + (tail > 0 ? 1 : 0);
  const std::shared_ptr<const Impl::Plan> full_plan = impl.PlanFor(block, bf16_);
  const std::shared_ptr<const Impl::Plan> tail_plan =
      tail > 0 ? impl.PlanFor(tail, bf16_) : nullptr;
  std::int64_t widest = width, multiply_adds = 0;
  for (const Impl::Layer& layer : impl.layers) {
    widest = std::max(widest, layer.out);
    multiply_adds += layer.in * layer.out;
  }
  multiply_adds *= members * rows;
  const std::size_t scratchpad_bytes =
      std::max(full_plan->scratchpad_bytes, tail_plan ? tail_plan->scratchpad_bytes : 0);
  const std::size_t element = bf16_ ? sizeof(std::uint16_t) : sizeof(float);
  const std::int64_t tasks = members * blocks;
  // Threads are started per call (tens of microseconds): only for products worth it.
  const int workers = multiply_adds >= kParallelMultiplyAdds
                          ? static_cast<int>(std::min<std::int64_t>(CoreCount(), tasks))
                          : 1;
  const float* all_states = states.data_ptr<float>();
  const float* all_actions = actions.data_ptr<float>();
  float* all_next = next.data_ptr<float>();

  ParallelRanges(tasks, workers, [&](std::int64_t first_task, std::int64_t end_task) {
    const ScopedOmpThreads one_thread(1);
    dnnl::stream stream(impl.engine);
    // This worker's buffers, left uninitialised (every byte read is written first): two for
    // the hidden activations, one scratchpad, each on a cache line of its own. malloc's 16-byte
    // alignment made every vector load of the activations straddle two cache lines: the
    // products ran at about 0.6 of their rate on AVX-512 (docs/PERFORMANCE.md, v0.8).
    const std::size_t activation_bytes =
        (static_cast<std::size_t>(block * widest) * element + 63) / 64 * 64;
    const std::size_t scratch_bytes = std::max<std::size_t>(scratchpad_bytes, 1);
    const CacheAlignedBytes buffers(2 * activation_bytes + scratch_bytes);
    std::uint8_t* const ping = buffers.get();
    std::uint8_t* const pong = ping + activation_bytes;
    const memory scratch({{static_cast<memory::dim>(scratch_bytes)}, memory::data_type::u8,
                          memory::format_tag::a},
                         impl.engine, pong + activation_bytes);
    for (std::int64_t task = first_task; task < end_task; ++task) {
      const std::int64_t m = task / blocks, b = task % blocks;
      const std::int64_t first_row = b * block;
      const std::int64_t count = std::min(block, rows - first_row);
      const Impl::Plan& plan = count == block ? *full_plan : *tail_plan;
      const std::int64_t offset = m * rows + first_row;
      const float* s = all_states + offset * s_dim;
      const float* a = all_actions + offset * a_dim;
      if (bf16_) {
        impl.NormalizedInputs(reinterpret_cast<std::uint16_t*>(ping), s, a, count, ToBf16);
      } else {
        impl.NormalizedInputs(reinterpret_cast<float*>(ping), s, a, count,
                              [](float value) { return value; });
      }
      impl.RunLayers(plan, m, ping, pong, all_next + offset * s_dim, scratch, stream);
    }
  });
  return next;
}

#else  // without oneDNN: the class exists so that callers compile; constructing it throws.

struct OnednnEnsembleForward::Impl {};

OnednnEnsembleForward::OnednnEnsembleForward(bool bf16) : bf16_(bf16) {
  std::string why_not;
  OnednnForwardAvailable(bf16, &why_not);
  Fail("the oneDNN prediction backend is not available: {}", why_not);
}

OnednnEnsembleForward::~OnednnEnsembleForward() = default;

void OnednnEnsembleForward::SetWeights(const std::vector<torch::Tensor>&,
                                       const std::vector<torch::Tensor>&, const torch::Tensor&,
                                       const torch::Tensor&, const torch::Tensor&,
                                       const torch::Tensor&, bool) {}

torch::Tensor OnednnEnsembleForward::Predict(const torch::Tensor&, const torch::Tensor&) const {
  Fail("the oneDNN prediction backend is not available");
}

#endif

}  // namespace cmbrl
