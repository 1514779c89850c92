#include "cmbrl/models/onednn_training.h"

#include <torch/torch.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/core/parallel.h"

#ifdef CMBRL_HAVE_ONEDNN
#include "cmbrl/models/onednn_common.h"
#endif

namespace cmbrl {

#ifdef CMBRL_HAVE_ONEDNN

namespace {

using dnnl::memory;
using onednn::ScopedOmpThreads;
using Tag = memory::format_tag;

constexpr memory::data_type kF32 = memory::data_type::f32;
// Below this many multiply-adds a step stays on the calling thread.
constexpr std::int64_t kParallelMultiplyAdds = std::int64_t{1} << 20;

// A float32 matrix in row-major (ab) or transposed (ba) layout.
memory::desc Matrix(std::int64_t rows, std::int64_t columns, Tag tag = Tag::ab) {
  return memory::desc({rows, columns}, kF32, tag);
}

// Column sums of a (rows, columns) matrix: a bias's gradient.
void SumRows(const float* __restrict matrix, std::int64_t rows, std::int64_t columns,
             float* __restrict sums) {
  std::fill_n(sums, columns, 0.0f);
  for (std::int64_t r = 0; r < rows; ++r) {
    const float* __restrict row = matrix + r * columns;
    for (std::int64_t j = 0; j < columns; ++j) sums[j] += row[j];
  }
}

// The gradient through a ReLU: kept where its output was positive, zero elsewhere.
void MaskByRelu(const float* __restrict output, std::int64_t count, float* __restrict grad) {
  for (std::int64_t i = 0; i < count; ++i) grad[i] = output[i] > 0.0f ? grad[i] : 0.0f;
}

// The mean squared error of `rows` predictions (rows, out_dim) against the targets of the
// picked rows, and its gradient times `scale` written to `grad` (rows, out_dim).
double SquaredErrorGradient(const float* prediction, const float* all_targets,
                            const std::int64_t* picks, std::int64_t rows, std::int64_t out_dim,
                            float scale, float* grad) {
  double squares = 0.0;
  for (std::int64_t r = 0; r < rows; ++r) {
    const float* target = all_targets + picks[r] * out_dim;
    for (std::int64_t j = 0; j < out_dim; ++j) {
      const float error = prediction[r * out_dim + j] - target[j];
      squares += static_cast<double>(error) * error;
      grad[r * out_dim + j] = scale * error;
    }
  }
  return squares / static_cast<double>(rows * out_dim);
}

}  // namespace

struct OnednnEnsembleTraining::Impl {
  // The primitives of one batch size B, layer by layer. A layer's input is (B, in), its output
  // (B, out), its weights (in, out), all row-major.
  struct Plan {
    std::vector<dnnl::matmul> forward;       // (B, in) x (in, out) + bias [, ReLU]
    std::vector<dnnl::matmul> weight_grads;  // (in, B) [transposed input] x (B, out)
    std::vector<dnnl::matmul> input_grads;   // (B, out) x (out, in) [transposed weights]; l >= 1
    std::size_t scratchpad_bytes = 1;
  };

  dnnl::engine engine{dnnl::engine::kind::cpu, 0};
  std::vector<std::int64_t> sizes;  // input, hidden..., output
  std::map<std::int64_t, Plan> plans;
  std::vector<torch::Tensor> weight_grads, bias_grads;  // like the parameters

  std::size_t layers() const { return sizes.size() - 1; }
  const Plan& PlanFor(std::int64_t rows);

  memory Wrap(std::int64_t rows, std::int64_t columns, const void* data, Tag tag = Tag::ab) const {
    return memory(Matrix(rows, columns, tag), engine, const_cast<void*>(data));
  }

  // Member m's forward pass over the `rows` gathered inputs at the start of `hidden`, each
  // layer's output written after its input; returns every layer's input, then the prediction.
  std::vector<float*> Forward(const Plan& plan, std::int64_t m, std::int64_t rows,
                              const std::vector<torch::Tensor>& weights,
                              const std::vector<torch::Tensor>& biases, float* hidden,
                              const memory& scratch, dnnl::stream& stream) const {
    std::vector<float*> inputs = {hidden};
    for (std::size_t l = 0; l < layers(); ++l) {
      const std::int64_t in = sizes[l], out = sizes[l + 1];
      float* output = inputs.back() + rows * in;
      plan.forward[l].execute(
          stream, {{DNNL_ARG_SRC, Wrap(rows, in, inputs.back())},
                   {DNNL_ARG_WEIGHTS, Wrap(in, out, weights[l].data_ptr<float>() + m * in * out)},
                   {DNNL_ARG_BIAS, Wrap(1, out, biases[l].data_ptr<float>() + m * out)},
                   {DNNL_ARG_DST, Wrap(rows, out, output)},
                   {DNNL_ARG_SCRATCHPAD, scratch}});
      inputs.push_back(output);
    }
    stream.wait();
    return inputs;
  }

  // Member m's backward pass from `grad`, the loss's gradient at the top (rows, out), through
  // every layer (`layer_inputs` from Forward): its weight and bias gradients written to
  // weight_grads and bias_grads; `spare` (as large as grad) holds the gradient below a layer.
  void Backward(const Plan& plan, std::int64_t m, std::int64_t rows,
                const std::vector<torch::Tensor>& weights, const std::vector<float*>& layer_inputs,
                float* grad, float* spare, const memory& scratch, dnnl::stream& stream) {
    // grad holds the gradient of the layer's output (before its ReLU).
    for (std::size_t l = layers(); l-- > 0;) {
      const std::int64_t in = sizes[l], out = sizes[l + 1];
      float* bias_grad = bias_grads[l].data_ptr<float>() + m * out;
      SumRows(grad, rows, out, bias_grad);
      plan.weight_grads[l].execute(
          stream,
          {{DNNL_ARG_SRC, Wrap(in, rows, layer_inputs[l], Tag::ba)},
           {DNNL_ARG_WEIGHTS, Wrap(rows, out, grad)},
           {DNNL_ARG_DST, Wrap(in, out, weight_grads[l].data_ptr<float>() + m * in * out)},
           {DNNL_ARG_SCRATCHPAD, scratch}});
      if (l == 0) break;
      plan.input_grads[l].execute(
          stream, {{DNNL_ARG_SRC, Wrap(rows, out, grad)},
                   {DNNL_ARG_WEIGHTS,
                    Wrap(out, in, weights[l].data_ptr<float>() + m * in * out, Tag::ba)},
                   {DNNL_ARG_DST, Wrap(rows, in, spare)},
                   {DNNL_ARG_SCRATCHPAD, scratch}});
      stream.wait();
      // Through the ReLU below: zero where its output was zero.
      MaskByRelu(layer_inputs[l], rows * in, spare);
      std::swap(grad, spare);
    }
    stream.wait();
  }
};

const OnednnEnsembleTraining::Impl::Plan& OnednnEnsembleTraining::Impl::PlanFor(std::int64_t rows) {
  if (auto found = plans.find(rows); found != plans.end()) return found->second;
  // Made single-threaded, as every call runs: a primitive may fix its blocking by the count.
  const ScopedOmpThreads one_thread(1);
  Plan plan;
  const auto make = [&](const memory::desc& source, const memory::desc& weights,
                        const memory::desc* bias, const memory::desc& destination, bool relu) {
    dnnl::post_ops post;
    if (relu) post.append_eltwise(1.0f, dnnl::algorithm::eltwise_relu, 0.0f, 0.0f);
    dnnl::primitive_attr attributes;
    attributes.set_post_ops(post);
    attributes.set_scratchpad_mode(dnnl::scratchpad_mode::user);  // per task: thread-safe
    const dnnl::matmul::primitive_desc description(
        bias != nullptr ? dnnl::matmul::desc(source, weights, *bias, destination)
                        : dnnl::matmul::desc(source, weights, destination),
        attributes, engine);
    plan.scratchpad_bytes =
        std::max(plan.scratchpad_bytes, description.scratchpad_desc().get_size());
    return dnnl::matmul(description);
  };
  for (std::size_t l = 0; l < layers(); ++l) {
    const std::int64_t in = sizes[l], out = sizes[l + 1];
    const memory::desc bias = Matrix(1, out);
    plan.forward.push_back(
        make(Matrix(rows, in), Matrix(in, out), &bias, Matrix(rows, out), l + 1 < layers()));
    plan.weight_grads.push_back(
        make(Matrix(in, rows, Tag::ba), Matrix(rows, out), nullptr, Matrix(in, out), false));
    plan.input_grads.push_back(l == 0 ? dnnl::matmul()
                                      : make(Matrix(rows, out), Matrix(out, in, Tag::ba), nullptr,
                                             Matrix(rows, in), false));
  }
  return plans.emplace(rows, std::move(plan)).first->second;
}

OnednnEnsembleTraining::OnednnEnsembleTraining(std::vector<std::int64_t> layer_sizes)
    : impl_(std::make_unique<Impl>()) {
  Require(layer_sizes.size() >= 2, "oneDNN training: {} layer sizes, expected at least 2",
          layer_sizes.size());
  impl_->sizes = std::move(layer_sizes);
}

double OnednnEnsembleTraining::Gradients(std::vector<torch::Tensor>& weights,
                                         std::vector<torch::Tensor>& biases,
                                         const torch::Tensor& inputs_in,
                                         const torch::Tensor& targets_in,
                                         const torch::Tensor& batch_in,
                                         const std::function<void(std::int64_t)>& after_member) {
  Impl& impl = *impl_;
  const std::size_t layers = impl.layers();
  Require(weights.size() == layers && biases.size() == layers,
          "oneDNN training: {} weight and {} bias tensors for {} layers", weights.size(),
          biases.size(), layers);
  const torch::Tensor inputs = inputs_in.contiguous();
  const torch::Tensor targets = targets_in.contiguous();
  const torch::Tensor batch = batch_in.to(torch::kLong).contiguous();
  const std::int64_t members = batch.size(0), rows = batch.size(1);
  const std::int64_t in_dim = impl.sizes.front(), out_dim = impl.sizes.back();
  Require(inputs.size(1) == in_dim && targets.size(1) == out_dim,
          "oneDNN training: inputs (n, {}) and targets (n, {}), expected {} and {} columns",
          inputs.size(1), targets.size(1), in_dim, out_dim);
  if (impl.weight_grads.empty() || impl.weight_grads[0].size(0) != members) {
    impl.weight_grads.clear();
    impl.bias_grads.clear();
    for (std::size_t l = 0; l < layers; ++l) {
      impl.weight_grads.push_back(torch::empty_like(weights[l]));
      impl.bias_grads.push_back(torch::empty_like(biases[l]));
    }
  }
  const Impl::Plan& plan = impl.PlanFor(rows);

  // Per member: the layers' inputs (the gathered rows, then each hidden layer's ReLU output),
  // the top's output, two gradient buffers and a scratchpad.
  std::int64_t activations = 0, widest = 0, multiply_adds = 0;
  for (std::size_t l = 0; l < layers; ++l) {
    activations += rows * impl.sizes[l];
    widest = std::max(widest, impl.sizes[l + 1]);
    multiply_adds += 3 * impl.sizes[l] * impl.sizes[l + 1];
  }
  multiply_adds *= members * rows;
  const int workers = multiply_adds >= kParallelMultiplyAdds
                          ? static_cast<int>(std::min<std::int64_t>(CoreCount(), members))
                          : 1;
  std::vector<double> member_loss(static_cast<std::size_t>(members), 0.0);
  const float* all_inputs = inputs.data_ptr<float>();
  const float* all_targets = targets.data_ptr<float>();
  const std::int64_t* all_rows = batch.data_ptr<std::int64_t>();
  const std::int64_t n = inputs.size(0);
  // The mean squared error's gradient: 2 (prediction - target) / (B x out).
  const auto scale = static_cast<float>(2.0 / static_cast<double>(rows * out_dim));

  {
    // The gradients' tensors are in place before they are computed, so that `after_member` can
    // read a member's as soon as it is made.
    const torch::NoGradGuard no_grad;
    for (std::size_t l = 0; l < layers; ++l) {
      weights[l].mutable_grad() = impl.weight_grads[l];
      biases[l].mutable_grad() = impl.bias_grads[l];
    }
  }
  ParallelRanges(members, workers, [&](std::int64_t first, std::int64_t end) {
    const ScopedOmpThreads one_thread(1);
    dnnl::stream stream(impl.engine);
    std::vector<float> hidden(static_cast<std::size_t>(activations + rows * out_dim));
    std::vector<float> grad_a(static_cast<std::size_t>(rows * widest));
    std::vector<float> grad_b(static_cast<std::size_t>(rows * widest));
    std::vector<std::uint8_t> scratch_bytes(plan.scratchpad_bytes);
    const memory scratch(
        {{static_cast<memory::dim>(scratch_bytes.size())}, memory::data_type::u8, Tag::a},
        impl.engine, scratch_bytes.data());
    for (std::int64_t m = first; m < end; ++m) {
      // The member's rows, gathered.
      const std::int64_t* picks = all_rows + m * rows;
      for (std::int64_t r = 0; r < rows; ++r) {
        Require(picks[r] >= 0 && picks[r] < n, "oneDNN training: row {} of {}", picks[r], n);
        std::copy_n(all_inputs + picks[r] * in_dim, in_dim, hidden.data() + r * in_dim);
      }
      std::vector<float*> layer_inputs =
          impl.Forward(plan, m, rows, weights, biases, hidden.data(), scratch, stream);
      const float* prediction = layer_inputs.back();
      layer_inputs.pop_back();
      member_loss[static_cast<std::size_t>(m)] = SquaredErrorGradient(
          prediction, all_targets, picks, rows, out_dim, scale, grad_a.data());
      impl.Backward(plan, m, rows, weights, layer_inputs, grad_a.data(), grad_b.data(), scratch,
                    stream);
      if (after_member) after_member(m);
    }
  });
  double loss = 0.0;
  for (const double value : member_loss) loss += value;
  return loss;
}

#else  // without oneDNN: the class exists so that callers compile; constructing it throws.

struct OnednnEnsembleTraining::Impl {};

OnednnEnsembleTraining::OnednnEnsembleTraining(std::vector<std::int64_t>) {
  Fail("the oneDNN training backend is not available: this build has no oneDNN");
}

double OnednnEnsembleTraining::Gradients(std::vector<torch::Tensor>&, std::vector<torch::Tensor>&,
                                         const torch::Tensor&, const torch::Tensor&,
                                         const torch::Tensor&,
                                         const std::function<void(std::int64_t)>&) {
  Fail("the oneDNN training backend is not available");
}

#endif

OnednnEnsembleTraining::~OnednnEnsembleTraining() = default;

}  // namespace cmbrl
