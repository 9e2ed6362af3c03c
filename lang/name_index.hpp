#pragma once
/// The map from a declared name to its declaration's index. A generated model declares hundreds
/// of thousands of names and every element looks its terminals up, so the map is open-addressed
/// (tsl::robin_set, hashes stored beside the entries): a lookup reads one bucket array instead of
/// a linked node per entry. A bucket holds only the declaration's index (12 bytes with its hash and
/// probe distance, where a name view and an index took 32): the name is read from the declaration.

#include <tsl/robin_set.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <string_view>

namespace thermnet::lang {

/// Declared name -> index of its declaration in `Decls` (a container of declarations with a
/// `name`, indexed by position, which must outlive the index and keep the names of the entered
/// declarations unchanged).
template <typename Decls> class NameIndex {
public:
  /// An empty index over `decls`.
  explicit NameIndex(const Decls& decls) : set_(0, Hash{&decls}, Equal{&decls}) {}

  /// Room for `count` names, buckets filled up to `load` (robin-hood hashing stays fast well
  /// above the default of 0.5).
  void reserve(std::size_t count, float load) {
    set_.max_load_factor(load);
    set_.reserve(count);
  }
  /// The index of the declaration with this name, or -1.
  int find(std::string_view name) const {
    auto it = set_.find(name);
    return it == set_.end() ? -1 : *it;
  }
  /// Enters declaration `index` under its name; -1 when entered, else the index of the
  /// declaration that has the name already (nothing is entered).
  int insert(int index) {
    auto [it, fresh] = set_.insert(index);
    return fresh ? -1 : *it;
  }
  /// Takes a name out.
  void erase(std::string_view name) { set_.erase(name); }

private:
  struct Hash {
    const Decls* decls;
    using is_transparent = void;
    std::size_t operator()(std::string_view name) const {
      return std::hash<std::string_view>()(name);
    }
    std::size_t operator()(int index) const { return (*this)(name_of(decls, index)); }
  };
  struct Equal {
    const Decls* decls;
    using is_transparent = void;
    bool operator()(int a, int b) const { return name_of(decls, a) == name_of(decls, b); }
    bool operator()(int a, std::string_view b) const { return name_of(decls, a) == b; }
    bool operator()(std::string_view a, int b) const { return a == name_of(decls, b); }
  };
  static std::string_view name_of(const Decls* decls, int index) {
    return (*decls)[static_cast<std::size_t>(index)].name;
  }

  tsl::robin_set<int, Hash, Equal, std::allocator<int>, /*StoreHash=*/true> set_;
};

} // namespace thermnet::lang
