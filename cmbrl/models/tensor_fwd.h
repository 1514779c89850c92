// A forward declaration of LibTorch's tensor, so that interfaces can name it without pulling in
// LibTorch's headers (they cost seconds per translation unit).
#pragma once

namespace at {
class Tensor;
}  // namespace at

namespace torch {
using at::Tensor;
}  // namespace torch
