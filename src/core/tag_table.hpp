// TagTable: any number of tags per object, and the objects that carry a tag, both ways; the
// thesis's way to address groups ("every grain of the bed", "the lid walls"), and what a
// GroupBehavior reads. The model is the Tk canvas: tagging is idempotent, an unknown tag is
// simply empty, and a tag that looks like a number is refused so it cannot be taken for an id.
//
// Iteration order is deterministic and history-based: a tag lists its objects in the order they
// were tagged, an object lists its tags in the order it got them. Removal leaves a tombstone in
// the tag's member array (so removing a grain from a tag of 10^6 costs O(1), not a shift), and
// the array is compacted once tombstones outnumber members, which keeps the order and the cost
// amortised O(1). Per-object data is indexed by the handle's slot index, not hashed.
#pragma once

#include <cassert>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/handle.hpp"

namespace demlab {

// Throws demlab::Error {VALUE TAG} unless tag is a usable tag: not empty,
// starting with a letter (any non-ASCII byte counts as one) or "_", and holding no white space,
// control character or any of {}[]"\$; (so it stays one element of any list). Changes nothing.
void checkTagName(std::string_view tag);

template <class Kind = void>
class TagTable {
 public:
  using HandleT = Handle<Kind>;

  // Gives the live object h the tag. Returns true if h did not have it already.
  // Throws demlab::Error {VALUE TAG} for a malformed tag, changing nothing. Tags left on an
  // earlier object of the same slot (one never passed to removeObject) are dropped first.
  bool add(HandleT h, std::string_view tag) {
    assert(!h.isNull());
    checkTagName(tag);
    ObjectTags& o = objectFor(h);
    const uint32_t t = intern(tag);
    for (const Entry& e : o.entries) {
      if (e.tag == t) return false;
    }
    TagData& td = tags_[t];
    o.entries.push_back({t, static_cast<uint32_t>(td.members.size())});
    td.members.push_back(h);
    ++td.live;
    return true;
  }

  // Takes the tag off h. Returns true if h had it.
  bool remove(HandleT h, std::string_view tag) {
    auto it = tagIds_.find(tag);
    ObjectTags* o = objectIfCurrent(h);
    if (it == tagIds_.end() || o == nullptr) return false;
    for (size_t k = 0; k < o->entries.size(); ++k) {
      if (o->entries[k].tag != it->second) continue;
      bury(o->entries[k]);
      o->entries.erase(o->entries.begin() + static_cast<std::ptrdiff_t>(k));
      maybeCompact(it->second);
      return true;
    }
    return false;
  }

  // Takes every tag off h (call it when the object is removed). Returns how many it had.
  size_t removeObject(HandleT h) {
    ObjectTags* o = objectIfCurrent(h);
    if (o == nullptr) return 0;
    std::vector<Entry> entries;
    entries.swap(o->entries);
    for (const Entry& e : entries) bury(e);
    for (const Entry& e : entries) maybeCompact(e.tag);
    return entries.size();
  }

  // Returns true if h has the tag.
  bool has(HandleT h, std::string_view tag) const {
    auto it = tagIds_.find(tag);
    const ObjectTags* o = objectIfCurrent(h);
    if (it == tagIds_.end() || o == nullptr) return false;
    for (const Entry& e : o->entries) {
      if (e.tag == it->second) return true;
    }
    return false;
  }

  // Returns the objects carrying the tag, in the order they were tagged; empty for an unknown
  // tag.
  std::vector<HandleT> objects(std::string_view tag) const {
    std::vector<HandleT> out;
    out.reserve(count(tag));
    forEach(tag, [&](HandleT h) { out.push_back(h); });
    return out;
  }

  // Calls f(handle) for every object carrying the tag, in the order they were tagged. f must
  // not change this table.
  template <class F>
  void forEach(std::string_view tag, F&& f) const {
    auto it = tagIds_.find(tag);
    if (it == tagIds_.end()) return;
    for (HandleT h : tags_[it->second].members) {
      if (!h.isNull()) f(h);
    }
  }

  // Returns the number of objects carrying the tag.
  size_t count(std::string_view tag) const {
    auto it = tagIds_.find(tag);
    return it == tagIds_.end() ? 0 : tags_[it->second].live;
  }

  // Returns the tags of h, in the order h got them.
  std::vector<std::string_view> tagsOf(HandleT h) const {
    std::vector<std::string_view> out;
    if (const ObjectTags* o = objectIfCurrent(h)) {
      for (const Entry& e : o->entries) out.push_back(tags_[e.tag].name);
    }
    return out;
  }

  // Returns every tag carried by at least one object, sorted (byte order).
  std::vector<std::string_view> tags() const {
    std::vector<std::string_view> out;
    for (const auto& [name, t] : tagIds_) {
      if (tags_[t].live > 0) out.push_back(name);
    }
    return out;
  }

  // Returns the length of the tag's member array, tombstones included (for tests of the
  // compaction policy).
  size_t storedMembers(std::string_view tag) const {
    auto it = tagIds_.find(tag);
    return it == tagIds_.end() ? 0 : tags_[it->second].members.size();
  }

  // Removes every tag from every object.
  void clear() {
    tags_.clear();
    tagIds_.clear();
    objects_.clear();
  }

 private:
  struct Entry {
    uint32_t tag;
    uint32_t pos;  // index of the object in tags_[tag].members
  };
  struct ObjectTags {
    uint32_t generation = 0;  // of the object the entries belong to
    std::vector<Entry> entries;
  };
  struct TagData {
    std::string name;
    std::vector<HandleT> members;  // a null handle is a tombstone
    uint32_t live = 0;
  };

  // Returns the id of tag, creating it if new. Tag ids are never reused; there are few tags.
  uint32_t intern(std::string_view tag) {
    auto it = tagIds_.find(tag);
    if (it != tagIds_.end()) return it->second;
    const auto t = static_cast<uint32_t>(tags_.size());
    tags_.push_back(TagData{std::string(tag), {}, 0});
    tagIds_.emplace(std::string(tag), t);
    return t;
  }

  // Returns the entry list of h, made current: a list left by an older object of the slot is
  // emptied first.
  ObjectTags& objectFor(HandleT h) {
    if (h.index >= objects_.size()) objects_.resize(size_t{h.index} + 1);
    ObjectTags& o = objects_[h.index];
    if (o.generation != h.generation) {
      removeObject(HandleT{h.index, o.generation});
      o.generation = h.generation;
    }
    return o;
  }

  // Returns the entry list of h, or null if h has never been tagged.
  ObjectTags* objectIfCurrent(HandleT h) {
    if (h.index >= objects_.size() || objects_[h.index].generation != h.generation) return nullptr;
    return &objects_[h.index];
  }
  const ObjectTags* objectIfCurrent(HandleT h) const {
    return const_cast<TagTable*>(this)->objectIfCurrent(h);
  }

  // Turns the member slot of e into a tombstone.
  void bury(const Entry& e) {
    tags_[e.tag].members[e.pos] = HandleT{};
    --tags_[e.tag].live;
  }

  // Compacts the tag's members, in order, once tombstones outnumber live members; updates
  // the position recorded for each object that moves.
  void maybeCompact(uint32_t t) {
    TagData& td = tags_[t];
    const size_t dead = td.members.size() - td.live;
    if (td.live > 0 && (dead <= td.live || dead < 16)) return;
    uint32_t w = 0;
    for (HandleT h : td.members) {
      if (h.isNull()) continue;
      for (Entry& e : objects_[h.index].entries) {
        if (e.tag == t) e.pos = w;
      }
      td.members[w++] = h;
    }
    td.members.resize(w);
  }

  std::vector<TagData> tags_;
  std::map<std::string, uint32_t, std::less<>> tagIds_;
  std::vector<ObjectTags> objects_;  // indexed by handle slot index
};

}  // namespace demlab
