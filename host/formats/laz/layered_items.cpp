// RGB14, RGBNIR14 and BYTE14 decoding (LASzip item version 3). Colours are coded byte by byte: a symbol says
// which bytes changed, red's bytes are corrected from the last red, and green and blue from the last value
// plus red's change (blue: plus the mean of red's and green's), clamped to a byte. NIR's two bytes and each
// extra byte are corrected from their last value alone. All byte arithmetic wraps modulo 256.
#include "layered_items.h"

#include <array>
#include <cstring>

namespace mv::laz {

namespace {

uint32_t layered_clamp_byte(int32_t v) { return v <= 0 ? 0u : v >= 255 ? 255u : static_cast<uint32_t>(v); }

}  // namespace

// One context's colour models (only those of non-empty layers) and its last R, G, B, NIR.
struct ColourDecoder::Context {
  struct Rgb {
    SymbolModel changed{128};
    std::array<SymbolModel, 6> diff{SymbolModel(256), SymbolModel(256), SymbolModel(256),
                                    SymbolModel(256), SymbolModel(256), SymbolModel(256)};
  };
  struct Nir {
    SymbolModel changed{4};
    std::array<SymbolModel, 2> diff{SymbolModel(256), SymbolModel(256)};
  };
  std::optional<Rgb> rgb;
  std::optional<Nir> nir;
  uint16_t last[4] = {0, 0, 0, 0};
};

namespace {

// Fresh models built once and copied (much cheaper than building them again, which matters for small chunks).
// Read-only once built, so threads share them.
const ColourDecoder::Context::Rgb& layered_fresh_rgb() {
  static const ColourDecoder::Context::Rgb fresh;
  return fresh;
}
const ColourDecoder::Context::Nir& layered_fresh_nir() {
  static const ColourDecoder::Context::Nir fresh;
  return fresh;
}
const SymbolModel& layered_fresh_byte() {
  static const SymbolModel fresh(256);
  return fresh;
}

}  // namespace

ColourDecoder::ColourDecoder(const uint8_t* first, unsigned context, bool with_nir, const LayerBytes* layers)
    : rgb_(open_layer(layers[0], with_nir ? "RGBNIR14 RGB" : "RGB14")),
      nir_(with_nir ? open_layer(layers[1], "RGBNIR14 NIR") : std::nullopt),
      current_(context & 3),
      with_nir_(with_nir) {
  uint16_t from[4] = {0, 0, 0, 0};
  for (size_t i = 0; i < (with_nir ? 4u : 3u); ++i)
    from[i] = static_cast<uint16_t>(first[2 * i] | first[2 * i + 1] << 8);
  open_context(current_, from);
}

ColourDecoder::~ColourDecoder() = default;

ColourDecoder::Context& ColourDecoder::open_context(unsigned context, const uint16_t* from) {
  auto ctx = std::make_unique<Context>();
  if (rgb_) ctx->rgb.emplace(layered_fresh_rgb());
  if (nir_) ctx->nir.emplace(layered_fresh_nir());
  std::memcpy(ctx->last, from, sizeof ctx->last);
  contexts_[context] = std::move(ctx);
  return *contexts_[context];
}

size_t ColourDecoder::overrun() const {
  return (rgb_ ? rgb_->overrun() : 0) + (nir_ ? nir_->overrun() : 0);
}

void ColourDecoder::next(unsigned context, uint8_t* out) {
  context &= 3;
  // The values predicted from: the current context's, kept (version 3) across a switch to an existing context.
  uint16_t* last = contexts_[current_]->last;
  if (context != current_) {
    current_ = context;
    if (!contexts_[context]) last = open_context(context, last).last;
  }
  Context& ch = *contexts_[current_];

  uint32_t r, g, b;
  if (rgb_) {
    ArithmeticDecoder& dec = *rgb_;
    Context::Rgb& m = *ch.rgb;
    const uint32_t changed = dec.decode_symbol(m.changed);
    const uint32_t last_r_lo = last[0] & 255u, last_r_hi = last[0] >> 8;
    const uint32_t last_g_lo = last[1] & 255u, last_g_hi = last[1] >> 8;
    const uint32_t last_b_lo = last[2] & 255u, last_b_hi = last[2] >> 8;
    const uint32_t r_lo = changed & 1 ? (dec.decode_symbol(m.diff[0]) + last_r_lo) & 255u : last_r_lo;
    const uint32_t r_hi = changed & 2 ? (dec.decode_symbol(m.diff[1]) + last_r_hi) & 255u : last_r_hi;
    r = r_lo | r_hi << 8;
    if (changed & (1u << 6)) {  // green and blue differ from red
      int32_t d = static_cast<int32_t>(r_lo) - static_cast<int32_t>(last_r_lo);
      uint32_t g_lo = last_g_lo, b_lo = last_b_lo;
      if (changed & (1u << 2))
        g_lo = (dec.decode_symbol(m.diff[2]) + layered_clamp_byte(d + static_cast<int32_t>(last_g_lo))) & 255u;
      if (changed & (1u << 4)) {
        const uint32_t corr = dec.decode_symbol(m.diff[4]);
        d = (d + (static_cast<int32_t>(g_lo) - static_cast<int32_t>(last_g_lo))) / 2;
        b_lo = (corr + layered_clamp_byte(d + static_cast<int32_t>(last_b_lo))) & 255u;
      }
      d = static_cast<int32_t>(r_hi) - static_cast<int32_t>(last_r_hi);
      uint32_t g_hi = last_g_hi, b_hi = last_b_hi;
      if (changed & (1u << 3))
        g_hi = (dec.decode_symbol(m.diff[3]) + layered_clamp_byte(d + static_cast<int32_t>(last_g_hi))) & 255u;
      if (changed & (1u << 5)) {
        const uint32_t corr = dec.decode_symbol(m.diff[5]);
        d = (d + (static_cast<int32_t>(g_hi) - static_cast<int32_t>(last_g_hi))) / 2;
        b_hi = (corr + layered_clamp_byte(d + static_cast<int32_t>(last_b_hi))) & 255u;
      }
      g = g_lo | g_hi << 8;
      b = b_lo | b_hi << 8;
    } else {
      g = b = r;
    }
    last[0] = static_cast<uint16_t>(r);
    last[1] = static_cast<uint16_t>(g);
    last[2] = static_cast<uint16_t>(b);
  } else {
    r = last[0];
    g = last[1];
    b = last[2];
  }
  out[0] = static_cast<uint8_t>(r);
  out[1] = static_cast<uint8_t>(r >> 8);
  out[2] = static_cast<uint8_t>(g);
  out[3] = static_cast<uint8_t>(g >> 8);
  out[4] = static_cast<uint8_t>(b);
  out[5] = static_cast<uint8_t>(b >> 8);
  if (!with_nir_) return;

  uint32_t nir = last[3];
  if (nir_) {
    ArithmeticDecoder& dec = *nir_;
    Context::Nir& m = *ch.nir;
    const uint32_t changed = dec.decode_symbol(m.changed);
    const uint32_t lo = changed & 1 ? (dec.decode_symbol(m.diff[0]) + (nir & 255u)) & 255u : nir & 255u;
    const uint32_t hi = changed & 2 ? (dec.decode_symbol(m.diff[1]) + (nir >> 8)) & 255u : nir >> 8;
    nir = lo | hi << 8;
    last[3] = static_cast<uint16_t>(nir);
  }
  out[6] = static_cast<uint8_t>(nir);
  out[7] = static_cast<uint8_t>(nir >> 8);
}

// One context's models (one per coded byte) and its last bytes.
struct Byte14Decoder::Context {
  std::vector<SymbolModel> models;
  std::vector<uint8_t> last;
};

Byte14Decoder::Byte14Decoder(const uint8_t* first, unsigned context, uint16_t size, const LayerBytes* layers)
    : size_(size), current_(context & 3) {
  for (uint16_t i = 0; i < size; ++i) {
    if (layers[i].empty()) continue;
    coded_.push_back(i);
    decoders_.push_back(*open_layer(layers[i], "BYTE14"));
  }
  open_context(current_, first);
}

Byte14Decoder::~Byte14Decoder() = default;

Byte14Decoder::Context& Byte14Decoder::open_context(unsigned context, const uint8_t* from) {
  auto ctx = std::make_unique<Context>();
  ctx->models.reserve(coded_.size());
  ctx->models.assign(coded_.size(), layered_fresh_byte());
  ctx->last.assign(from, from + size_);
  contexts_[context] = std::move(ctx);
  return *contexts_[context];
}

size_t Byte14Decoder::overrun() const {
  size_t n = 0;
  for (const ArithmeticDecoder& d : decoders_) n += d.overrun();
  return n;
}

void Byte14Decoder::next(unsigned context, uint8_t* out) {
  context &= 3;
  // As for colours: version 3 keeps predicting from the previous context's bytes after a switch.
  uint8_t* last = contexts_[current_]->last.data();
  if (context != current_) {
    current_ = context;
    if (!contexts_[context]) last = open_context(context, last).last.data();
  }
  Context& ch = *contexts_[current_];
  for (size_t j = 0; j < coded_.size(); ++j) {
    const uint16_t i = coded_[j];
    last[i] = static_cast<uint8_t>(last[i] + decoders_[j].decode_symbol(ch.models[j]));
  }
  std::memcpy(out, last, size_);
}

}  // namespace mv::laz
