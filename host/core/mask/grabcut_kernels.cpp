#include "grabcut_kernels.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/grabcut.h"
#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv::mask {

namespace {

constexpr uint32_t kGcLocal = 64;  // work-items per group (the sums' shared arrays are per group)
// Where each reduction's 64-bit sums start in the sums buffer.
constexpr uint32_t kSumBeta = 0, kSumSmooth = 1, kSumData = 2, kSumLabels = 3, kSumMoments = 4, kSumKmeans = 104,
                   kSumChannels = 144;

}  // namespace

GrabCutConsts::GrabCutConsts() : v(MV_GC_CONSTS, 0.0) {
  for (int j = 0; j < 16; ++j) v[MV_GC_EXP2 + j] = std::exp2(-j / 16.0);
  double fact = 1;
  for (int i = 0; i <= 10; ++i) {
    if (i > 0) fact *= i;
    v[MV_GC_EXPC + i] = (i % 2 ? -1.0 : 1.0) / fact;
  }
  for (int i = 1; i <= 12; ++i) v[MV_GC_LOGA + i - 1] = (i % 2 ? 1.0 : -1.0) / i;
  // ln2 / 16 in two parts (fdlibm's split of ln2, divided by 16): 32 significant bits, then the next 53, so
  // t * hi is exact for every t the kernels take and r = x - t ln2/16 is good to far below an ulp.
  v[MV_GC_K16] = 16 / std::log(2.0);
  v[MV_GC_LN2HI] = 0x1.62e42feep-5;
  v[MV_GC_LN2LO] = 0x1.a39ef35793c76p-37;
  for (int j = 0; j <= 128; ++j) {
    const double c = 1 + j / 32.0;
    v[MV_GC_LOGC + j] = std::log(c);
    v[MV_GC_INVC + j] = 1 / c;
  }
  v[MV_GC_UNDER] = -std::log(1e-300);
  v[MV_GC_CLAMP] = 690.8;
  v[MV_GC_ZERO] = -std::log(std::numeric_limits<double>::denorm_min());
}

void GrabCutConsts::set_mixture(int side, const std::array<Gaussian, kComponents>& g) {
  for (int k = 0; k < kComponents; ++k) {
    double* at = &v[MV_GC_MIX + (side * kComponents + k) * 16];
    std::copy(g[k].mean, g[k].mean + 3, at);
    std::copy(g[k].inverse, g[k].inverse + 9, at + 3);
    at[12] = g[k].energy;
    at[13] = g[k].weight > 0 ? 1 : 0;
  }
}

void GrabCutConsts::set_centre(int side, int k, const double (&c)[3]) {
  std::copy(c, c + 3, &v[MV_GC_CENTRES + (side * kComponents + k) * 3]);
}

GrabCutKernels::GrabCutKernels(Device& dev, const RasterImage& image, const std::vector<uint8_t>& labels)
    : dev_(dev), w_(image.width), h_(image.height), n_(uint64_t{image.width} * image.height) {
  if (image.channels != 1 && image.channels != 3) throw Error("grabcut: images have 1 or 3 channels");
  if (image.samples.size() != n_ * image.channels) throw Error("grabcut: the image's samples do not match its size");
  if (labels.size() != n_) throw Error("grabcut: the start labels do not match the image");
  if (n_ == 0) throw Error("grabcut: the image is empty");
  if (n_ * 8 > kMaxDeviceItems)  // edge capacities are indexed with 32 bits
    throw Error("grabcut: " + std::to_string(w_) + " x " + std::to_string(h_) + " pixels is over the " +
                std::to_string(kMaxDeviceItems / 8) + " a GrabCut graph takes");
  const uint64_t sample_words = (n_ * image.channels + 1) / 2;
  samples_ = dev.alloc(sample_words * 4, "grabcut image samples");
  std::vector<uint16_t> padded(sample_words * 2, 0);
  std::copy(image.samples.begin(), image.samples.end(), padded.begin());
  dev.upload(samples_, padded.data(), sample_words * 4);
  colour_ = dev.alloc(n_ * 4, "grabcut colours");
  labels_ = dev.alloc(n_ * 4, "grabcut labels");
  comp_ = dev.alloc(n_ * 4, "grabcut components");
  consts_ = dev.alloc(MV_GC_CONSTS * 8, "grabcut constants");
  terms_ = dev.alloc(n_ * 16, "grabcut data terms");
  sums_ = dev.alloc(kSumChannels * 8, "grabcut sums");
  found_ = dev.alloc(8, "grabcut seeds");
  const std::vector<uint32_t> wide(labels.begin(), labels.end());
  dev.upload(labels_, wide.data(), n_ * 4);
  dev.fill(comp_, 0, n_ * 4);
  MvGrabCutParams p = params();
  p.channels = image.channels;
  p.max_value = image.max_value;
  dev.dispatch(dev.kernel(KernelId::grabcut_colours), pixel_groups(), kGcLocal, {&samples_, &colour_}, p);
  dev.barrier();
}

MvGrabCutParams GrabCutKernels::params() const {
  MvGrabCutParams p{};
  p.width = w_, p.height = h_, p.pixels = static_cast<uint32_t>(n_);
  return p;
}

uint32_t GrabCutKernels::pixel_groups() const { return dev_.groups_for(n_, kGcLocal); }

// Groups for a summing kernel: each flushes its sums once, so CPU devices get a few per compute unit; enough
// everywhere that no work-item runs past the device's loop cap. A loop-capped device (lavapipe) counts the
// iterations of every loop of the invocation together, and a pixel of the data terms runs up to about 250 of
// them (8 exps of 20, 2 logs of 11, the components' loops): a work-item takes at most cap / 512 pixels.
uint32_t GrabCutKernels::sum_groups() const {
  const DeviceInfo& info = dev_.info();
  uint64_t groups = (n_ + kGcLocal - 1) / kGcLocal;
  if (!info.massively_parallel) groups = std::min<uint64_t>(groups, uint64_t{std::max(info.compute_units, 1u)} * 4);
  if (info.max_loop_iterations > 0) {
    const uint64_t per_item = std::max<uint64_t>(1, info.max_loop_iterations / 512);
    groups = std::max<uint64_t>(groups, (n_ + kGcLocal * per_item - 1) / (kGcLocal * per_item));
  }
  return dev_.groups_for(groups * kGcLocal, kGcLocal);
}

std::vector<uint64_t> GrabCutKernels::run_sums(KernelId id, std::initializer_list<const Buffer*> buffers,
                                               MvGrabCutParams p, uint32_t channels) {
  dev_.fill(sums_, 0, uint64_t{channels} * 8, uint64_t{p.sum_at} * 8);
  dev_.barrier();
  dev_.dispatch(dev_.kernel(id), sum_groups(), kGcLocal, buffers, p);
  dev_.barrier();
  std::vector<uint64_t> out(channels);
  dev_.download(sums_, out.data(), uint64_t{channels} * 8, uint64_t{p.sum_at} * 8);
  return out;
}

void GrabCutKernels::upload_consts(const GrabCutConsts& c) {
  dev_.upload(consts_, c.v.data(), MV_GC_CONSTS * 8);
}

uint64_t GrabCutKernels::beta_sum() {
  MvGrabCutParams p = params();
  p.sum_at = kSumBeta;
  return run_sums(KernelId::grabcut_beta_sum, {&colour_, &sums_}, p, 1)[0];
}

uint64_t GrabCutKernels::smooth_sum() {
  MvGrabCutParams p = params();
  p.sum_at = kSumSmooth;
  if (weights_.empty()) weights_ = dev_.alloc(n_ * 32, "grabcut smoothness weights");
  return run_sums(KernelId::grabcut_smooth_sum, {&colour_, &consts_, &weights_, &sums_}, p, 1)[0];
}

void GrabCutKernels::edges(std::vector<uint32_t>& out) {
  if (weights_.empty()) throw Error("grabcut: the edges take the weights smooth_sum leaves; call it first");
  if (edges_.empty()) edges_ = dev_.alloc(n_ * 32, "grabcut edge capacities");
  dev_.dispatch(dev_.kernel(KernelId::grabcut_edges), pixel_groups(), kGcLocal, {&weights_, &consts_, &edges_}, params());
  dev_.barrier();
  out.resize(n_ * 8);
  dev_.download(edges_, out.data(), n_ * 32);
}

uint64_t GrabCutKernels::data(bool own_side_only) {
  MvGrabCutParams p = params();
  p.mode = own_side_only ? 1 : 0;
  p.sum_at = kSumData;
  return run_sums(KernelId::grabcut_data, {&colour_, &labels_, &comp_, &consts_, &terms_, &sums_}, p, 1)[0];
}

void GrabCutKernels::terminals(std::vector<uint32_t>& source, std::vector<uint32_t>& sink) {
  if (q_.empty()) q_ = dev_.alloc(n_ * 8, "grabcut terminal capacities");
  dev_.dispatch(dev_.kernel(KernelId::grabcut_terminals), pixel_groups(), kGcLocal, {&terms_, &consts_, &q_}, params());
  dev_.barrier();
  source.resize(n_), sink.resize(n_);
  dev_.download(q_, source.data(), n_ * 4);
  dev_.download(q_, sink.data(), n_ * 4, n_ * 4);
}

std::array<Moments, 2> GrabCutKernels::moments() {
  MvGrabCutParams p = params();
  p.sum_at = kSumMoments;
  const std::vector<uint64_t> s = run_sums(KernelId::grabcut_moments, {&colour_, &labels_, &comp_, &sums_}, p, 100);
  std::array<Moments, 2> m{};
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < kComponents; ++k)
      for (int c = 0; c < 10; ++c) m[side][k][c] = s[(side * kComponents + k) * 10 + c];
  return m;
}

std::array<std::array<std::array<uint64_t, 4>, kComponents>, 2> GrabCutKernels::kmeans(const uint32_t (&centres)[2]) {
  MvGrabCutParams p = params();
  p.sum_at = kSumKmeans;
  p.centres_bg = centres[0], p.centres_fg = centres[1];
  const std::vector<uint64_t> s = run_sums(KernelId::grabcut_kmeans, {&colour_, &labels_, &comp_, &consts_, &sums_}, p, 40);
  std::array<std::array<std::array<uint64_t, 4>, kComponents>, 2> out{};
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < kComponents; ++k)
      for (int c = 0; c < 4; ++c) out[side][k][c] = s[(side * kComponents + k) * 4 + c];
  return out;
}

std::array<uint64_t, 2> GrabCutKernels::seed_d2(uint32_t mode, uint32_t sides, const uint32_t (&colour)[2]) {
  for (int s = 0; s < 2; ++s)
    if (d2_[s].empty()) {
      d2_[s] = dev_.alloc(n_ * 4, "grabcut k-means++ distances");
      scan_[s] = dev_.alloc((n_ + 1) * 8, "grabcut k-means++ running sums");
    }
  MvGrabCutParams p = params();
  p.mode = mode, p.seeding = sides, p.colour_bg = colour[0], p.colour_fg = colour[1];
  dev_.dispatch(dev_.kernel(KernelId::grabcut_seed_d2), pixel_groups(), kGcLocal, {&colour_, &labels_, &d2_[0], &d2_[1]}, p);
  dev_.barrier();
  std::array<uint64_t, 2> total{};
  for (int s = 0; s < 2; ++s)
    if (sides & (1u << s)) exclusive_scan64(dev_, d2_[s], scan_[s], n_);
  dev_.barrier();
  for (int s = 0; s < 2; ++s)
    if (sides & (1u << s)) dev_.download(scan_[s], &total[s], 8, n_ * 8);
  return total;
}

std::array<uint32_t, 2> GrabCutKernels::seed_find(uint32_t sides, const uint64_t (&pick)[2], uint32_t (&colour)[2]) {
  MvGrabCutParams p = params();
  p.seeding = sides;
  p.pick_bg_lo = static_cast<uint32_t>(pick[0]), p.pick_bg_hi = static_cast<uint32_t>(pick[0] >> 32);
  p.pick_fg_lo = static_cast<uint32_t>(pick[1]), p.pick_fg_hi = static_cast<uint32_t>(pick[1] >> 32);
  dev_.dispatch(dev_.kernel(KernelId::grabcut_seed_find), pixel_groups(), kGcLocal, {&scan_[0], &scan_[1], &found_}, p);
  dev_.barrier();
  std::array<uint32_t, 2> found{};
  dev_.download(found_, found.data(), 8);
  for (int s = 0; s < 2; ++s)
    if (sides & (1u << s)) dev_.download(colour_, &colour[s], 4, uint64_t{found[s]} * 4);
  return found;
}

uint64_t GrabCutKernels::update_labels(const std::vector<uint8_t>& source_side) {
  if (source_side.size() != n_) throw Error("grabcut: the cut does not match the image");
  const uint64_t bytes = (n_ + 3) / 4 * 4;  // whole words: one byte a pixel, four to a word
  if (side_.empty()) side_ = dev_.alloc(bytes, "grabcut cut sides");
  side_bytes_.assign(bytes, 0);
  std::copy(source_side.begin(), source_side.end(), side_bytes_.begin());
  dev_.upload(side_, side_bytes_.data(), bytes);
  MvGrabCutParams p = params();
  p.sum_at = kSumLabels;
  return run_sums(KernelId::grabcut_labels, {&side_, &labels_, &sums_}, p, 1)[0];
}

std::vector<uint8_t> GrabCutKernels::labels() const {
  std::vector<uint32_t> wide(n_);
  dev_.download(labels_, wide.data(), n_ * 4);
  return std::vector<uint8_t>(wide.begin(), wide.end());
}

std::vector<uint32_t> GrabCutKernels::colours() const {
  std::vector<uint32_t> out(n_);
  dev_.download(colour_, out.data(), n_ * 4);
  return out;
}

std::vector<uint32_t> GrabCutKernels::components() const {
  std::vector<uint32_t> out(n_);
  dev_.download(comp_, out.data(), n_ * 4);
  return out;
}

std::vector<double> GrabCutKernels::terms() const {
  std::vector<double> out(n_ * 2);
  dev_.download(terms_, out.data(), n_ * 16);
  return out;
}

void GrabCutKernels::set_components(const std::vector<uint32_t>& comp) {
  if (comp.size() != n_) throw Error("grabcut: the components do not match the image");
  dev_.upload(comp_, comp.data(), n_ * 4);
}

}  // namespace mv::mask
