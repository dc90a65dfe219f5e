// POINT14 (LASzip item version 3) decoding: how each field of a LAS 1.4 point is predicted from the previous
// point of its scanner channel and which model codes the correction. The contexts, the order in which symbols
// are read and the wrap-around arithmetic are the format: they follow LASzip's layered reader exactly.
//
// Integer fields wrap as LASzip's do (X/Y/Z and GPS time in unsigned arithmetic), so no input overflows a
// signed integer.
#include "point14_item.h"

#include <array>
#include <string>
#include <vector>

#include "median5.h"

namespace mv::laz {

// One LAS 1.4 point core, unpacked.
struct Point14Decoder::Fields {
  uint32_t x = 0, y = 0, z = 0;  // int32 bits
  uint16_t intensity = 0;
  uint8_t return_number = 0, number_of_returns = 0;  // 4 bits each
  uint8_t classification_flags = 0;                  // 4 bits
  uint8_t scanner_channel = 0;                       // 2 bits
  uint8_t scan_direction = 0, edge_of_flight_line = 0;
  uint8_t classification = 0, user_data = 0;
  uint16_t scan_angle = 0;  // int16 bits
  uint16_t point_source_id = 0;
  uint64_t gps_time = 0;  // double bits
  bool gps_time_change = false;  // whether the GPS time of this point changed (a context of the next point)
};

namespace {

// Contexts from the number of returns n and the return number r (LASzip's tables).
constexpr uint8_t kPoint14ReturnMap[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5}, {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3}, {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5}};

// The return level |n - r|, saturated at 7.
constexpr uint8_t point14_return_level(unsigned n, unsigned r) {
  const unsigned d = n > r ? n - r : r - n;
  return static_cast<uint8_t>(d < 7 ? d : 7);
}

// GPS time coding: multipliers of the last difference up to kPoint14GpsMulti, down to kPoint14GpsMultiMinus,
// then the symbols for "full 64-bit value" and "switch to another of the four time sequences".
constexpr int32_t kPoint14GpsMulti = 500;
constexpr int32_t kPoint14GpsMultiMinus = -10;
constexpr uint32_t kPoint14GpsCodeFull = kPoint14GpsMulti - kPoint14GpsMultiMinus + 1;  // 511
constexpr uint32_t kPoint14GpsSymbols = kPoint14GpsMulti - kPoint14GpsMultiMinus + 5;   // 515
// A sound stream switches sequence at most once per point; more switches than this is corrupt data.
constexpr int kPoint14MaxGpsSwitches = 16;

// Little-endian loads and stores (compilers turn these into single moves).
template <typename T>
T point14_load(const uint8_t* p) {
  T v = 0;
  for (size_t i = 0; i < sizeof(T); ++i) v |= static_cast<T>(static_cast<T>(p[i]) << (8 * i));
  return v;
}

template <typename T>
void point14_store(uint8_t* p, T v) {
  for (size_t i = 0; i < sizeof(T); ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}

Point14Decoder::Fields point14_unpack(const uint8_t* p) {
  Point14Decoder::Fields f;
  f.x = point14_load<uint32_t>(p);
  f.y = point14_load<uint32_t>(p + 4);
  f.z = point14_load<uint32_t>(p + 8);
  f.intensity = point14_load<uint16_t>(p + 12);
  f.return_number = p[14] & 15;
  f.number_of_returns = p[14] >> 4;
  f.classification_flags = p[15] & 15;
  f.scanner_channel = (p[15] >> 4) & 3;
  f.scan_direction = (p[15] >> 6) & 1;
  f.edge_of_flight_line = p[15] >> 7;
  f.classification = p[16];
  f.user_data = p[17];
  f.scan_angle = point14_load<uint16_t>(p + 18);
  f.point_source_id = point14_load<uint16_t>(p + 20);
  f.gps_time = point14_load<uint64_t>(p + 22);
  return f;
}

void point14_pack(const Point14Decoder::Fields& f, uint8_t* p) {
  point14_store(p, f.x);
  point14_store(p + 4, f.y);
  point14_store(p + 8, f.z);
  point14_store(p + 12, f.intensity);
  p[14] = static_cast<uint8_t>(f.return_number | f.number_of_returns << 4);
  p[15] = static_cast<uint8_t>(f.classification_flags | f.scanner_channel << 4 | f.scan_direction << 6 |
                               f.edge_of_flight_line << 7);
  p[16] = f.classification;
  p[17] = f.user_data;
  point14_store(p + 18, f.scan_angle);
  point14_store(p + 20, f.point_source_id);
  point14_store(p + 22, f.gps_time);
}

// a * b with the two's-complement wrap-around LASzip's 32-bit products have.
int32_t point14_wrapping_product(int32_t a, int32_t b) {
  return static_cast<int32_t>(static_cast<uint32_t>(a) * static_cast<uint32_t>(b));
}

uint64_t point14_add_signed(uint64_t a, int32_t d) { return a + static_cast<uint64_t>(static_cast<int64_t>(d)); }

SymbolModel& point14_model(std::optional<SymbolModel>& m, uint32_t symbols) {
  if (!m) m.emplace(symbols);
  return *m;
}

}  // namespace

// Everything one scanner channel's points are coded with. Models that LASzip creates on first use start in
// the same state as those created eagerly, so only the large per-value tables are created lazily.
struct Point14Decoder::Channel {
  std::array<SymbolModel, 8> changed_values{SymbolModel(128), SymbolModel(128), SymbolModel(128),
                                            SymbolModel(128), SymbolModel(128), SymbolModel(128),
                                            SymbolModel(128), SymbolModel(128)};
  SymbolModel scanner_channel{3};
  std::optional<SymbolModel> number_of_returns[16], return_number[16];
  SymbolModel return_number_gps_same{13};
  IntegerDecoder dx{32, 2}, dy{32, 22}, z{32, 20};
  std::optional<SymbolModel> classification[64], flags[64], user_data[64];
  IntegerDecoder intensity{16, 4}, scan_angle{16, 2}, point_source_id{16};
  SymbolModel gps_multi{kPoint14GpsSymbols}, gps_zero_diff{5};
  IntegerDecoder gps_time{32, 9};

  Median5 x_median[12], y_median[12];
  uint32_t last_z[8] = {};
  uint16_t last_intensity[8] = {};
  // Four interleaved GPS time sequences: their last times, last 32-bit differences, and how often a
  // difference far from the last one was seen in a row.
  uint64_t gps_last_time[4] = {0, 0, 0, 0};
  int32_t gps_last_diff[4] = {0, 0, 0, 0};
  int32_t gps_extremes[4] = {0, 0, 0, 0};
  uint32_t gps_last = 0, gps_next = 0;

  Fields last;

  // Every model fresh; the predictions of a channel that starts after the point `from`.
  void start_from(const Fields& from) {
    last = from;
    last.gps_time_change = false;
    for (uint32_t& v : last_z) v = from.z;
    for (uint16_t& v : last_intensity) v = from.intensity;
    gps_last_time[0] = from.gps_time;
  }
};

namespace {

// A channel with every model fresh, built once: copying it is much cheaper than building the models again
// (which matters for small chunks). Read-only once built, so threads share it.
const Point14Decoder::Channel& point14_fresh_channel() {
  static const Point14Decoder::Channel fresh;
  return fresh;
}

// Channels of this thread's finished chunks, kept for its next chunk: refreshing one by copy-assignment reuses
// its memory instead of allocating several hundred model tables again.
constexpr size_t kPoint14SpareChannels = 4;
thread_local std::vector<std::unique_ptr<Point14Decoder::Channel>> point14_spare_channels;

}  // namespace

std::optional<ArithmeticDecoder> open_layer(LayerBytes layer, const char* what) {
  if (layer.empty()) return std::nullopt;
  std::optional<ArithmeticDecoder> dec(std::in_place, layer.begin, layer.end);
  if (dec->overrun() != 0)
    throw LazError(std::string("the ") + what + " layer of " + std::to_string(layer.end - layer.begin) +
                   " bytes is too short to hold any coded value");
  return dec;
}

Point14Decoder::Point14Decoder(const uint8_t* first, const LayerBytes* layers, uint16_t version)
    : xy_(open_layer(layers[0], "POINT14 channel/returns/XY")),
      z_(open_layer(layers[1], "POINT14 Z")),
      classification_(open_layer(layers[2], "POINT14 classification")),
      flags_(open_layer(layers[3], "POINT14 flags")),
      intensity_(open_layer(layers[4], "POINT14 intensity")),
      scan_angle_(open_layer(layers[5], "POINT14 scan angle")),
      user_data_(open_layer(layers[6], "POINT14 user data")),
      point_source_(open_layer(layers[7], "POINT14 point source")),
      gps_time_(open_layer(layers[8], "POINT14 GPS time")),
      hand_on_channel_(version >= 4) {
  point14_spare_channels.reserve(kPoint14SpareChannels);  // so that the destructor returns channels without allocating
  const Fields f = point14_unpack(first);
  current_ = items_context_ = f.scanner_channel;
  open_channel(current_, f);
}

Point14Decoder::~Point14Decoder() {
  for (std::unique_ptr<Channel>& ch : channels_)
    if (ch && point14_spare_channels.size() < point14_spare_channels.capacity())
      point14_spare_channels.push_back(std::move(ch));
}

Point14Decoder::Channel& Point14Decoder::open_channel(unsigned channel, const Fields& from) {
  if (!point14_spare_channels.empty()) {
    channels_[channel] = std::move(point14_spare_channels.back());
    point14_spare_channels.pop_back();
    *channels_[channel] = point14_fresh_channel();
  } else {
    channels_[channel] = std::make_unique<Channel>(point14_fresh_channel());
  }
  channels_[channel]->start_from(from);
  return *channels_[channel];
}

size_t Point14Decoder::overrun() const {
  size_t n = 0;
  for (const auto* d : {&xy_, &z_, &classification_, &flags_, &intensity_, &scan_angle_, &user_data_,
                        &point_source_, &gps_time_})
    if (*d) n += (*d)->overrun();
  return n;
}

void Point14Decoder::next(uint8_t* out) {
  if (!xy_) throw LazError("the POINT14 channel/returns/XY layer is empty but the chunk has more points");
  ArithmeticDecoder& xy = *xy_;
  Channel* ch = channels_[current_].get();
  Fields* last = &ch->last;

  // Which fields changed, in a context of the previous point's return (first? last?) and time change.
  const uint32_t lpr = (last->return_number == 1 ? 1u : 0u) |
                       (last->return_number >= last->number_of_returns ? 2u : 0u) |
                       (last->gps_time_change ? 4u : 0u);
  const uint32_t changed = xy.decode_symbol(ch->changed_values[lpr]);

  if (changed & (1u << 6)) {  // another scanner channel: its context, created from this one if new
    const uint32_t step = xy.decode_symbol(ch->scanner_channel);
    const unsigned channel = (current_ + step + 1) & 3;
    Channel* to = channels_[channel] ? channels_[channel].get() : &open_channel(channel, *last);
    current_ = channel;
    ch = to;
    last = &ch->last;
    last->scanner_channel = static_cast<uint8_t>(channel);
    items_context_ = channel;
  } else {
    items_context_ = hand_on_channel_ ? current_ : 0;
  }
  const bool point_source_change = changed & (1u << 5);
  const uint32_t gps_change = (changed >> 4) & 1;
  const bool scan_angle_change = changed & (1u << 3);

  uint32_t n = last->number_of_returns;
  uint32_t r = last->return_number;
  if (changed & (1u << 2)) {
    n = xy.decode_symbol(point14_model(ch->number_of_returns[n], 16));
    last->number_of_returns = static_cast<uint8_t>(n);
  }
  switch (changed & 3) {
    case 1: r = (r + 1) & 15; break;
    case 2: r = (r + 15) & 15; break;
    case 3:
      if (gps_change) r = xy.decode_symbol(point14_model(ch->return_number[r], 16));
      else r = (r + xy.decode_symbol(ch->return_number_gps_same) + 2) & 15;
      break;
    default: break;
  }
  last->return_number = static_cast<uint8_t>(r);

  const uint32_t map = kPoint14ReturnMap[n][r];
  const uint32_t level = point14_return_level(n, r);
  const uint32_t cpr = (r == 1 ? 2u : 0u) | (r >= n ? 1u : 0u);  // first (2) / last (1) return of the pulse
  const uint32_t single = n == 1 ? 1u : 0u;

  // X and Y: differences predicted by the median of the last five in the same return context.
  const uint32_t xy_ctx = (map << 1) | gps_change;
  int32_t diff = ch->dx.decode(xy, ch->x_median[xy_ctx].get(), single);
  last->x += static_cast<uint32_t>(diff);
  ch->x_median[xy_ctx].add(diff);
  uint32_t k = ch->dx.k();
  diff = ch->dy.decode(xy, ch->y_median[xy_ctx].get(), single + (k < 20 ? k & ~1u : 20u));
  last->y += static_cast<uint32_t>(diff);
  ch->y_median[xy_ctx].add(diff);

  if (z_) {
    k = (ch->dx.k() + ch->dy.k()) / 2;
    const int32_t z =
        ch->z.decode(*z_, static_cast<int32_t>(ch->last_z[level]), single + (k < 18 ? k & ~1u : 18u));
    last->z = static_cast<uint32_t>(z);
    ch->last_z[level] = static_cast<uint32_t>(z);
  }

  if (classification_) {
    const uint32_t ctx = ((last->classification & 0x1Fu) << 1) + (cpr == 3 ? 1u : 0u);
    last->classification =
        static_cast<uint8_t>(classification_->decode_symbol(point14_model(ch->classification[ctx], 256)));
  }

  if (flags_) {
    const uint32_t ctx = (uint32_t{last->edge_of_flight_line} << 5) | (uint32_t{last->scan_direction} << 4) |
                         last->classification_flags;
    const uint32_t f = flags_->decode_symbol(point14_model(ch->flags[ctx], 64));
    last->edge_of_flight_line = (f >> 5) & 1;
    last->scan_direction = (f >> 4) & 1;
    last->classification_flags = f & 15;
  }

  if (intensity_) {
    const uint32_t ctx = (cpr << 1) | gps_change;
    const auto v = static_cast<uint16_t>(ch->intensity.decode(*intensity_, ch->last_intensity[ctx], cpr));
    ch->last_intensity[ctx] = v;
    last->intensity = v;
  }

  if (scan_angle_ && scan_angle_change)
    last->scan_angle = static_cast<uint16_t>(
        ch->scan_angle.decode(*scan_angle_, static_cast<int16_t>(last->scan_angle), gps_change));

  if (user_data_) {
    SymbolModel& m = point14_model(ch->user_data[last->user_data / 4], 256);
    last->user_data = static_cast<uint8_t>(user_data_->decode_symbol(m));
  }

  if (point_source_ && point_source_change)
    last->point_source_id =
        static_cast<uint16_t>(ch->point_source_id.decode(*point_source_, last->point_source_id, 0));

  if (gps_time_ && gps_change) last->gps_time = decode_gps_time(*ch, *gps_time_);

  point14_pack(*last, out);
  last->gps_time_change = gps_change != 0;
}

// The next GPS time of the channel: a difference from the last time of one of four sequences, predicted by a
// multiple of that sequence's last difference, or a full 64-bit time that starts a new sequence.
uint64_t Point14Decoder::decode_gps_time(Channel& ch, ArithmeticDecoder& dec) {
  for (int switches = 0; switches <= kPoint14MaxGpsSwitches; ++switches) {
    uint32_t& seq = ch.gps_last;
    if (ch.gps_last_diff[seq] == 0) {
      const uint32_t multi = dec.decode_symbol(ch.gps_zero_diff);
      if (multi == 0) {  // a 32-bit difference
        const int32_t d = ch.gps_time.decode(dec, 0, 0);
        ch.gps_last_diff[seq] = d;
        ch.gps_last_time[seq] = point14_add_signed(ch.gps_last_time[seq], d);
        ch.gps_extremes[seq] = 0;
        return ch.gps_last_time[seq];
      }
      if (multi >= 2) {  // switch to another sequence and decode there
        seq = (seq + multi - 1) & 3;
        continue;
      }
    } else {
      const uint32_t multi = dec.decode_symbol(ch.gps_multi);
      if (multi == 1) {  // the last difference again, corrected
        ch.gps_last_time[seq] =
            point14_add_signed(ch.gps_last_time[seq], ch.gps_time.decode(dec, ch.gps_last_diff[seq], 1));
        ch.gps_extremes[seq] = 0;
        return ch.gps_last_time[seq];
      }
      if (multi < kPoint14GpsCodeFull) {  // a multiple of the last difference
        const int32_t last_diff = ch.gps_last_diff[seq];
        int32_t d;
        bool extreme = false;
        if (multi == 0) {
          d = ch.gps_time.decode(dec, 0, 7);
          extreme = true;
        } else if (multi < static_cast<uint32_t>(kPoint14GpsMulti)) {
          d = ch.gps_time.decode(dec, point14_wrapping_product(static_cast<int32_t>(multi), last_diff),
                                 multi < 10 ? 2 : 3);
        } else if (multi == static_cast<uint32_t>(kPoint14GpsMulti)) {
          d = ch.gps_time.decode(dec, point14_wrapping_product(kPoint14GpsMulti, last_diff), 4);
          extreme = true;
        } else {
          const int32_t m = kPoint14GpsMulti - static_cast<int32_t>(multi);  // -1 .. -10
          if (m > kPoint14GpsMultiMinus) {
            d = ch.gps_time.decode(dec, point14_wrapping_product(m, last_diff), 5);
          } else {
            d = ch.gps_time.decode(dec, point14_wrapping_product(kPoint14GpsMultiMinus, last_diff), 6);
            extreme = true;
          }
        }
        if (extreme && ++ch.gps_extremes[seq] > 3) {  // the differences have moved: adopt the new one
          ch.gps_last_diff[seq] = d;
          ch.gps_extremes[seq] = 0;
        }
        ch.gps_last_time[seq] = point14_add_signed(ch.gps_last_time[seq], d);
        return ch.gps_last_time[seq];
      }
      if (multi > kPoint14GpsCodeFull) {  // switch to another sequence and decode there
        seq = (seq + multi - kPoint14GpsCodeFull) & 3;
        continue;
      }
    }
    // A full time: its high 32 bits predicted by the last time's, its low 32 bits raw. It starts a sequence.
    ch.gps_next = (ch.gps_next + 1) & 3;
    const int32_t high = ch.gps_time.decode(dec, static_cast<int32_t>(ch.gps_last_time[seq] >> 32), 8);
    const uint32_t low = dec.read_int();
    seq = ch.gps_next;
    ch.gps_last_time[seq] = (uint64_t{static_cast<uint32_t>(high)} << 32) | low;
    ch.gps_last_diff[seq] = 0;
    ch.gps_extremes[seq] = 0;
    return ch.gps_last_time[seq];
  }
  throw LazError("the POINT14 GPS time layer switches time sequence endlessly");
}

}  // namespace mv::laz
