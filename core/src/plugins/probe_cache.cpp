#include "plugins/probe_cache.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace mh {

// A first line naming the format and the probe's version, then one line per
// library: usable (0 or 1), size, mtime (ns), content hash, path, reason,
// separated by tabs (paths with a tab or newline are not cached). Bump the
// version when the probe tests more: older verdicts are then probed again.
constexpr const char* kCacheHeader = "monohydra-probe-cache 2";

std::string ProbeCache::default_file() {
  if (const char* env = std::getenv("MONOHYDRA_PROBE_CACHE"); env != nullptr && *env != '\0')
    return std::string(env) == "off" ? std::string() : std::string(env);
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg == '/')
    return (fs::path(xdg) / "monohydra" / "probe-cache").string();
  if (const char* home = std::getenv("HOME"); home != nullptr && *home == '/')
    return (fs::path(home) / ".cache" / "monohydra" / "probe-cache").string();
  return {};
}

ProbeCache::ProbeCache(std::string file) : file_(std::move(file)) {
  if (file_.empty()) return;
  // Only a regular file of a sane size is a cache: a device (/dev/zero reads
  // forever, /dev/null would be replaced by the rename in save()), a FIFO
  // (blocks on open) or a huge file is no cache at all. A missing one is
  // created by save(), unless its name is taken by something else.
  std::error_code ec;
  const fs::file_status st = fs::status(file_, ec);
  constexpr std::uintmax_t kMaxCacheBytes = 16u << 20;
  if (!ec && fs::exists(st) &&
      (!fs::is_regular_file(st) || fs::file_size(file_, ec) > kMaxCacheBytes || ec)) {
    file_.clear();
    return;
  }
  std::ifstream in(file_);
  std::string header;
  if (!std::getline(in, header) || header != kCacheHeader) return;  // none, or an older probe's
  for (std::string line; std::getline(in, line);) {
    std::stringstream ss(line);
    std::string usable, size, mtime, content, path, reason;
    if (!std::getline(ss, usable, '\t') || !std::getline(ss, size, '\t') ||
        !std::getline(ss, mtime, '\t') || !std::getline(ss, content, '\t') ||
        !std::getline(ss, path, '\t'))
      continue;
    std::getline(ss, reason);
    try {
      Entry e{{std::stoull(size), std::stoll(mtime), std::stoull(content, nullptr, 16)},
              {usable == "1", reason}};
      entries_[path] = e;
    } catch (const std::exception&) {  // a damaged line is probed again
    }
  }
}

std::optional<std::uint64_t> ProbeCache::content_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a, 64 bits
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    const auto got = static_cast<size_t>(in.gcount());
    for (size_t i = 0; i < got; ++i) {
      h ^= static_cast<unsigned char>(buf[i]);
      h *= 0x100000001b3ULL;
    }
    if (!in) break;
  }
  return h;
}

std::optional<ProbeCache::Key> ProbeCache::stat_of(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  return Key{static_cast<std::uintmax_t>(st.st_size),
             static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec, 0};
}

std::optional<ProbeCache::Key> ProbeCache::key_of(const std::string& path) {
  auto key = stat_of(path);
  const auto content = key ? content_hash(path) : std::nullopt;
  if (!content) return std::nullopt;
  key->content = *content;
  return key;
}

std::optional<ProbeVerdict> ProbeCache::find(const std::string& canonical_path) const {
  if (file_.empty()) return std::nullopt;
  const auto it = entries_.find(canonical_path);
  if (it == entries_.end()) return std::nullopt;
  // Size and mtime first: the contents are read only when they agree.
  const Key& kept = it->second.key;
  const auto now = stat_of(canonical_path);
  if (!now || now->size != kept.size || now->mtime_ns != kept.mtime_ns) return std::nullopt;
  const auto content = content_hash(canonical_path);
  if (!content || *content != kept.content) return std::nullopt;
  return it->second.verdict;
}

void ProbeCache::remember(const std::string& canonical_path, const ProbeVerdict& verdict) {
  if (file_.empty() || canonical_path.find_first_of("\t\n") != std::string::npos) return;
  const auto key = key_of(canonical_path);
  if (!key) return;
  entries_[canonical_path] = Entry{*key, verdict};
  changed_ = true;
}

void ProbeCache::save() {
  if (file_.empty() || !changed_) return;
  changed_ = false;
  std::error_code ec;
  fs::create_directories(fs::path(file_).parent_path(), ec);
  // Another process may save at the same time: write aside, then rename.
  const std::string tmp = file_ + "." + std::to_string(::getpid()) + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    if (!out) return;
    out << kCacheHeader << '\n' << std::hex;
    for (const auto& [path, e] : entries_)
      out << (e.verdict.usable ? '1' : '0') << '\t' << std::dec << e.key.size << '\t'
          << e.key.mtime_ns << '\t' << std::hex << e.key.content << '\t' << path << '\t'
          << e.verdict.reason << '\n';
    if (!out.flush()) {
      out.close();
      fs::remove(tmp, ec);
      return;
    }
  }
  fs::rename(tmp, file_, ec);
  if (ec) fs::remove(tmp, ec);
}

}  // namespace mh
