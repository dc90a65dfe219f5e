// Kernels only the tests dispatch (tests/kernels/kernels.cmake): the layout probes and the kernel language's
// self-tests. They are embedded into the test executable alone, in a table of their own, so the library's
// table holds only the kernels it ships.
#pragma once
#include <string>

#include "kernel_table.h"
#include "megavox/device.h"
#include "megavox/error.h"
#include "test_kernel_ids.h"  // generated from tests/kernels/kernels.cmake

namespace mv::rt {
const EmbeddedKernel* find_test_kernel(TestKernelId id);  // nullptr when out of range
}  // namespace mv::rt

namespace mv::test {

// Built on first use, once per Device, and checked at every dispatch like a library kernel.
inline Kernel& test_kernel(Device& dev, TestKernelId id) {
  const rt::EmbeddedKernel* e = rt::find_test_kernel(id);
  if (!e) throw Error("no test kernel with id " + std::to_string(static_cast<uint32_t>(id)));
  return dev.kernel(*e);
}

}  // namespace mv::test
