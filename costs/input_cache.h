#ifndef EULERSPLAT_COSTS_INPUT_CACHE_H_
#define EULERSPLAT_COSTS_INPUT_CACHE_H_

#include <cstddef>
#include <initializer_list>
#include <map>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

namespace es {

// How an input image is recognised besides its buffer: its size and
// type, and a sample of its pixels (an empty image: none of them).
struct InputDescription {
  int rows = 0, cols = 0, type = 0;
  std::vector<unsigned char> sample;
};
InputDescription DescribeInput(const cv::Mat& image);
bool InputMatches(const cv::Mat& image, const InputDescription& described);

// What a loss computes from its training inputs alone (a target's SSIM
// statistics, the water losses' energies and bands), computed the first
// time those inputs are seen and kept while the values fit in a memory
// budget: training scores every frame many times and its inputs never
// change. Values past the budget are computed at each call into one spare
// slot. Inputs are known by their buffers, and a sample of each one's
// pixels is compared on every lookup, so a buffer freed and reused for
// another image is not mistaken for the old one; an input must not be
// changed in place while it may be looked up (a change between the
// sampled pixels would go unnoticed). Not thread-safe.
template <typename Value>
class InputCache {
 public:
  explicit InputCache(size_t budget_bytes) : budget_(budget_bytes) {}

  // The value of `inputs` (continuous images, or empty ones); on a miss,
  // make(Value*) fills it, and it is kept if its `bytes` fit, else made in
  // `spare` (default: the cache's own spare slot; a caller holding one
  // value while it gets another passes its own).
  template <typename Make>
  const Value& Get(std::initializer_list<const cv::Mat*> inputs,
                   size_t bytes, Make make, Value* spare = nullptr) {
    Key key;
    for (const cv::Mat* m : inputs) key.push_back(m->data);
    auto it = entries_.find(key);
    if (it != entries_.end()) {
      if (Matches(inputs, *it->second)) return it->second->value;
      // Another image now lives in one of those buffers: forget the old.
      used_ -= it->second->bytes;
      entries_.erase(it);
    }
    if (used_ + bytes > budget_) {
      if (spare == nullptr) spare = &spare_;
      make(spare);
      return *spare;
    }
    auto entry = std::make_unique<Entry>();
    for (const cv::Mat* m : inputs) entry->inputs.push_back(DescribeInput(*m));
    make(&entry->value);
    entry->bytes = bytes;
    used_ += bytes;
    const Value& value = entry->value;
    entries_.emplace(std::move(key), std::move(entry));
    return value;
  }

  size_t cached_values() const { return entries_.size(); }
  size_t cached_bytes() const { return used_; }

 private:
  using Key = std::vector<const void*>;
  struct Entry {
    std::vector<InputDescription> inputs;
    size_t bytes = 0;
    Value value;
  };

  static bool Matches(std::initializer_list<const cv::Mat*> inputs,
                      const Entry& entry) {
    size_t i = 0;
    for (const cv::Mat* m : inputs)
      if (!InputMatches(*m, entry.inputs[i++])) return false;
    return true;
  }

  size_t budget_;
  size_t used_ = 0;
  std::map<Key, std::unique_ptr<Entry>> entries_;
  Value spare_;
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_INPUT_CACHE_H_
