// Probing forks once per library; the verdicts are kept in a small file keyed
// by (canonical path, size, mtime, a hash of the contents) so that start-up
// stays fast and a library rebuilt with the same size and mtime is probed
// again. The file names the probe's version: a verdict of an older probe
// (which tested less) is not trusted.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "plugins/plugin_probe.hpp"

namespace mh {

class ProbeCache {
 public:
  // $MONOHYDRA_PROBE_CACHE: "off" for none, else the file to use; when unset,
  // $XDG_CACHE_HOME/monohydra/probe-cache, else ~/.cache/monohydra/probe-cache.
  static std::string default_file();

  explicit ProbeCache(std::string file);  // "" for no cache
  // The verdict kept for this library as it is now on disk, if any.
  std::optional<ProbeVerdict> find(const std::string& canonical_path) const;
  void remember(const std::string& canonical_path, const ProbeVerdict& verdict);
  // Writes the file (atomically) when something new was remembered; a cache
  // that cannot be written is silently not kept.
  void save();

 private:
  struct Key {
    std::uintmax_t size = 0;
    std::int64_t mtime_ns = 0;
    std::uint64_t content = 0;  // FNV-1a of the bytes
  };
  struct Entry {
    Key key;
    ProbeVerdict verdict;
  };
  static std::optional<Key> stat_of(const std::string& path);  // size and mtime only
  static std::optional<Key> key_of(const std::string& path);   // and the contents' hash
  static std::optional<std::uint64_t> content_hash(const std::string& path);

  std::string file_;
  std::map<std::string, Entry> entries_;  // by canonical path
  bool changed_ = false;
};

}  // namespace mh
