#include "cmbrl/models/onednn_forward.h"

#include <torch/torch.h>

#include <cstdint>
#include <cstring>
#include <map>
#include <mutex>

#include "cmbrl/core/check.h"
#include "cmbrl/core/cpu_features.h"

#ifdef CMBRL_HAVE_ONEDNN
#include <omp.h>
#include <oneapi/dnnl/dnnl.hpp>
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

#ifdef CMBRL_HAVE_ONEDNN

namespace {

using dnnl::memory;
using Dims = memory::dims;

// float32 -> bfloat16, rounding to nearest even (NaN stays a NaN).
std::uint16_t ToBf16(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  if ((bits & 0x7fffffffu) > 0x7f800000u) return static_cast<std::uint16_t>((bits >> 16) | 0x40u);
  bits += 0x7fffu + ((bits >> 16) & 1u);
  return static_cast<std::uint16_t>(bits >> 16);
}

// Sets the calling thread's OpenMP thread count for its lifetime, then puts the caller's back.
class ScopedOmpThreads {
 public:
  explicit ScopedOmpThreads(int threads) : before_(omp_get_max_threads()) {
    if (threads != before_) omp_set_num_threads(threads);
  }
  ~ScopedOmpThreads() {
    if (omp_get_max_threads() != before_) omp_set_num_threads(before_);
  }
  ScopedOmpThreads(const ScopedOmpThreads&) = delete;
  ScopedOmpThreads& operator=(const ScopedOmpThreads&) = delete;

 private:
  int before_;
};

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
  // oneDNN (OpenMP build) splits a product over the calling thread's OpenMP thread count, and
  // the split changes the sums' order: every call uses the count of the thread that built the
  // backend, so that a prediction's bits do not depend on which thread asks.
  int threads = omp_get_max_threads();
  std::vector<Layer> layers;
  std::vector<float> input_mean, input_std;
  std::int64_t members = 0, state_dim = 0, action_dim = 0;
  bool predict_delta = false;
  mutable std::mutex plans_mutex;
  mutable std::map<std::int64_t, std::shared_ptr<const Plan>> plans;

  std::shared_ptr<const Plan> PlanFor(std::int64_t rows, bool bf16) const;
};

std::shared_ptr<const OnednnEnsembleForward::Impl::Plan> OnednnEnsembleForward::Impl::PlanFor(
    std::int64_t rows, bool bf16) const {
  const std::lock_guard<std::mutex> lock(plans_mutex);
  if (auto found = plans.find(rows); found != plans.end()) return found->second;
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
  const std::shared_ptr<const Impl::Plan> plan = impl.PlanFor(rows, bf16_);

  // Normalised [state, action] rows, in the first product's type.
  const torch::ScalarType hidden = bf16_ ? torch::kBFloat16 : torch::kFloat;
  torch::Tensor input = torch::empty({members, rows, width}, torch::TensorOptions(hidden));
  const float* s = states.data_ptr<float>();
  const float* a = actions.data_ptr<float>();
  const float* mean = impl.input_mean.data();
  const float* std = impl.input_std.data();
  const std::int64_t total = members * rows;
  if (bf16_) {
    auto* out = reinterpret_cast<std::uint16_t*>(input.data_ptr());
    for (std::int64_t r = 0; r < total; ++r, out += width, s += s_dim, a += a_dim) {
      for (std::int64_t j = 0; j < s_dim; ++j) out[j] = ToBf16((s[j] - mean[j]) / std[j]);
      for (std::int64_t j = 0; j < a_dim; ++j) {
        out[s_dim + j] = ToBf16((a[j] - mean[s_dim + j]) / std[s_dim + j]);
      }
    }
  } else {
    float* out = input.data_ptr<float>();
    for (std::int64_t r = 0; r < total; ++r, out += width, s += s_dim, a += a_dim) {
      for (std::int64_t j = 0; j < s_dim; ++j) out[j] = (s[j] - mean[j]) / std[j];
      for (std::int64_t j = 0; j < a_dim; ++j) {
        out[s_dim + j] = (a[j] - mean[s_dim + j]) / std[s_dim + j];
      }
    }
  }

  const ScopedOmpThreads same_split(impl.threads);
  dnnl::stream stream(impl.engine);
  torch::Tensor scratchpad =
      torch::empty({static_cast<std::int64_t>(plan->scratchpad_bytes)}, torch::kByte);
  const memory scratch({{static_cast<memory::dim>(plan->scratchpad_bytes)},
                        memory::data_type::u8, memory::format_tag::a},
                       impl.engine, scratchpad.data_ptr());
  torch::Tensor source = input;
  for (std::size_t l = 0; l < impl.layers.size(); ++l) {
    const Impl::Layer& layer = impl.layers[l];
    const bool last = l + 1 == impl.layers.size();
    torch::Tensor destination =
        last ? next : torch::empty({members, rows, layer.out}, torch::TensorOptions(hidden));
    for (std::int64_t m = 0; m < members; ++m) {
      const memory src(plan->sources[l], impl.engine, source[m].data_ptr());
      const memory dst(plan->destinations[l], impl.engine, destination[m].data_ptr());
      const memory bias(plan->biases[l], impl.engine, layer.bias[m].data_ptr());
      plan->primitives[l].execute(stream, {{DNNL_ARG_SRC, src},
                                           {DNNL_ARG_WEIGHTS, plan->weights[l][m]},
                                           {DNNL_ARG_BIAS, bias},
                                           {DNNL_ARG_DST, dst},
                                           {DNNL_ARG_SCRATCHPAD, scratch}});
    }
    source = destination;
  }
  stream.wait();
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
