#include "bench/kernel_ceiling.h"

#include <torch/torch.h>

#include <memory>

#include "bench/bench_util.h"
#include "cmbrl/core/check.h"

#ifdef CMBRL_HAVE_ONEDNN
#include <oneapi/dnnl/dnnl.hpp>
#endif

namespace cmbrl::bench {

std::vector<ProductShape> ForwardShapes(std::int64_t members, std::int64_t rows,
                                        const std::vector<std::int64_t>& layer_sizes) {
  std::vector<ProductShape> shapes;
  for (size_t l = 0; l + 1 < layer_sizes.size(); ++l) {
    shapes.push_back({members, rows, layer_sizes[l], layer_sizes[l + 1]});
  }
  return shapes;
}

namespace {

// LibTorch's batched product: OpenBLAS for fp32 in Debian's build, its own kernels for bf16.
class TorchKernel final : public ChainKernel {
 public:
  TorchKernel(const std::vector<ProductShape>& shapes, torch::ScalarType type) : type_(type) {
    for (const ProductShape& s : shapes) {
      a_.push_back(torch::randn({s.batch, s.rows, s.inner}).to(type));
      b_.push_back(torch::randn({s.batch, s.inner, s.cols}).to(type));
      c_.push_back(torch::empty({s.batch, s.rows, s.cols}, torch::TensorOptions(type)));
    }
  }
  std::string name() const override {
    return type_ == torch::kFloat ? "openblas_fp32" : "libtorch_bf16";
  }
  double Seconds() override {
    const torch::NoGradGuard no_grad;
    return SecondsOf([this] {
      for (size_t i = 0; i < a_.size(); ++i) torch::bmm_out(c_[i], a_[i], b_[i]);
    });
  }

 private:
  torch::ScalarType type_;
  std::vector<torch::Tensor> a_, b_, c_;
};

#ifdef CMBRL_HAVE_ONEDNN
// oneDNN matmul primitives, weights reordered once into the layout each prefers.
class OnednnKernel final : public ChainKernel {
 public:
  OnednnKernel(const std::vector<ProductShape>& shapes, bool bf16) : bf16_(bf16) {
    using dnnl::memory;
    const memory::data_type type = bf16 ? memory::data_type::bf16 : memory::data_type::f32;
    dnnl::stream stream(engine_);
    for (const ProductShape& s : shapes) {
      const memory::desc a({s.batch, s.rows, s.inner}, type, memory::format_tag::abc);
      const memory::desc b({s.batch, s.inner, s.cols}, type, memory::format_tag::any);
      const memory::desc c({s.batch, s.rows, s.cols}, type, memory::format_tag::abc);
      const dnnl::matmul::primitive_desc pd(dnnl::matmul::desc(a, b, c), engine_);
      primitives_.emplace_back(pd);
      sources_.emplace_back(a, engine_);
      destinations_.emplace_back(c, engine_);
      const torch::Tensor plain_b = torch::randn({s.batch, s.inner, s.cols});
      memory plain({{s.batch, s.inner, s.cols}, memory::data_type::f32, memory::format_tag::abc},
                   engine_, plain_b.data_ptr<float>());
      weights_.emplace_back(pd.weights_desc(), engine_);
      dnnl::reorder(plain, weights_.back()).execute(stream, plain, weights_.back());
      const torch::Tensor plain_a = torch::randn({s.batch, s.rows, s.inner});
      memory plain_source(
          {{s.batch, s.rows, s.inner}, memory::data_type::f32, memory::format_tag::abc}, engine_,
          plain_a.data_ptr<float>());
      dnnl::reorder(plain_source, sources_.back()).execute(stream, plain_source, sources_.back());
    }
    stream.wait();
  }
  std::string name() const override { return bf16_ ? "onednn_bf16" : "onednn_fp32"; }
  double Seconds() override {
    dnnl::stream stream(engine_);
    return SecondsOf([&] {
      for (size_t i = 0; i < primitives_.size(); ++i) {
        primitives_[i].execute(stream, {{DNNL_ARG_SRC, sources_[i]},
                                        {DNNL_ARG_WEIGHTS, weights_[i]},
                                        {DNNL_ARG_DST, destinations_[i]}});
      }
      stream.wait();
    });
  }

 private:
  bool bf16_;
  dnnl::engine engine_{dnnl::engine::kind::cpu, 0};
  std::vector<dnnl::matmul> primitives_;
  std::vector<dnnl::memory> sources_, weights_, destinations_;
};
#endif

}  // namespace

std::vector<std::unique_ptr<ChainKernel>> CeilingKernels(const std::vector<ProductShape>& shapes,
                                                         const std::string& precision) {
  Require(precision == "fp32" || precision == "bf16",
          "ceiling precision is '{}': expected fp32 or bf16", precision);
  const bool bf16 = precision == "bf16";
  std::vector<std::unique_ptr<ChainKernel>> kernels;
  kernels.push_back(std::make_unique<TorchKernel>(shapes, bf16 ? torch::kBFloat16 : torch::kFloat));
#ifdef CMBRL_HAVE_ONEDNN
  try {
    kernels.push_back(std::make_unique<OnednnKernel>(shapes, bf16));
  } catch (const dnnl::error&) {
    // No oneDNN kernel for this precision on this CPU (bf16 without AVX-512): not a candidate.
  }
#endif
  return kernels;
}

ShapeCeiling::ShapeCeiling(std::vector<ProductShape> shapes, const std::string& precision,
                           int runs) {
  for (const ProductShape& s : shapes) flops_ += s.Flops();
  kernels_ = CeilingKernels(shapes, precision);
  double best_rate = 0.0;
  for (const auto& kernel : kernels_) {
    kernel->Seconds();  // warm-up
    std::vector<double> rates;
    for (int i = 0; i < std::max(3, runs); ++i) rates.push_back(flops_ / kernel->Seconds());
    const double rate = Median(rates);
    candidates_[kernel->name() + "_gflops"] = rate / 1e9;
    if (rate > best_rate) {
      best_rate = rate;
      best_ = kernel.get();
    }
  }
  candidates_["ceiling_kernel"] = best_->name();
}

double ShapeCeiling::Measure() { return flops_ / best_->Seconds(); }

}  // namespace cmbrl::bench
