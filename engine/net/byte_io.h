#pragma once
// Little-endian reading and writing of the wire format's scalars. The reader never reads past its
// span: every get checks the bytes left first and records the first shortfall, so decoders read a
// whole struct and check `ok()` once.
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

namespace rt::net {

static_assert(std::endian::native == std::endian::little, "the wire format is little-endian; so is this host");

class ByteWriter {
 public:
  explicit ByteWriter(std::vector<uint8_t>& out) : out_(out) {}
  template <typename T>
  void put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    const size_t at = out_.size();
    out_.resize(at + sizeof(T));
    std::memcpy(out_.data() + at, &value, sizeof(T));
  }
  void put_bytes(std::span<const uint8_t> bytes) { out_.insert(out_.end(), bytes.begin(), bytes.end()); }
  size_t size() const { return out_.size(); }

 private:
  std::vector<uint8_t>& out_;
};

class ByteReader {
 public:
  explicit ByteReader(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  template <typename T>
  T get() {
    static_assert(std::is_arithmetic_v<T>);
    T value{};
    if (!ok_ || left() < sizeof(T)) {
      ok_ = false;
      return value;
    }
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  std::span<const uint8_t> get_bytes(size_t count) {
    if (!ok_ || left() < count) {
      ok_ = false;
      return {};
    }
    auto span = bytes_.subspan(at_, count);
    at_ += count;
    return span;
  }
  size_t left() const { return bytes_.size() - at_; }
  size_t offset() const { return at_; }
  bool ok() const { return ok_; }

 private:
  std::span<const uint8_t> bytes_;
  size_t at_ = 0;
  bool ok_ = true;
};

}  // namespace rt::net
