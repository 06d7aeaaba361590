#pragma once
// The outbound queue of one receiver (a browser, a TCP client): bounded, and when full the
// oldest entry goes and is counted. A slow or vanished receiver so costs the producer one
// pop per frame and never more memory than `capacity` entries; a live view wants the newest
// pose, not a backlog. Not thread-safe: each owner uses it on one thread (its I/O thread).
#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>

namespace hullpose::skeleton_io {

template <typename T>
class DropOldestQueue {
 public:
  explicit DropOldestQueue(size_t capacity) : capacity_(capacity < 1 ? 1 : capacity) {}

  void push(T value) {
    if (items_.size() == capacity_) {
      items_.pop_front();
      ++dropped_;
    }
    items_.push_back(std::move(value));
    ++pushed_;
  }
  bool empty() const { return items_.empty(); }
  size_t size() const { return items_.size(); }
  size_t capacity() const { return capacity_; }
  T& front() { return items_.front(); }
  void pop() { items_.pop_front(); }
  int64_t dropped() const { return dropped_; }
  int64_t pushed() const { return pushed_; }

 private:
  size_t capacity_;
  std::deque<T> items_;
  int64_t dropped_ = 0, pushed_ = 0;
};

}  // namespace hullpose::skeleton_io
