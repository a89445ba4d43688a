#pragma once
/// \file comm_counter.hpp
/// \brief Messages and bytes a communication object has sent to other ranks (point-to-point; a
/// periodic image on the same rank is not counted), so that
/// scaling studies can report traffic that does not depend on the machine's core count.

namespace biota::core {

/// \brief Running totals of sent messages and payload bytes.
struct CommCounter {
  long long messages = 0;
  long long bytes = 0;
  void add(long long payload_bytes) {
    ++messages;
    bytes += payload_bytes;
  }
  CommCounter& operator+=(const CommCounter& o) {
    messages += o.messages;
    bytes += o.bytes;
    return *this;
  }
};

}  // namespace biota::core
