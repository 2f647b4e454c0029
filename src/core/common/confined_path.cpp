#include "art2part/common/confined_path.h"

#include <deque>
#include <system_error>

#include "art2part/geometry/mesh.h"

namespace art2part {

namespace fs = std::filesystem;

namespace {

constexpr int kMaxLinks = 40;              // as Linux's ELOOP limit for one lookup
constexpr std::size_t kMaxEchoed = 200;    // characters of a request repeated in a refusal

// The request as a refusal repeats it: control characters shown as '?', long ones cut (one line in any log).
std::string echoed(const std::string& requested) {
  std::string text = requested.substr(0, kMaxEchoed);
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return requested.size() > kMaxEchoed ? text + "..." : text;
}

}  // namespace

std::string outsideRefusal(const FolderConfinement& confinement, const std::string& requested) {
  return "'" + echoed(requested) + "': path is outside the configured " + confinement.description;
}

fs::path resolvedPath(const fs::path& absolute) {
  std::deque<fs::path> pending(absolute.begin(), absolute.end());
  if (!absolute.is_absolute() || pending.empty()) throw InputError("'" + absolute.string() + "' is not absolute");
  pending.pop_front();  // the root directory "/"
  fs::path result = absolute.root_path();
  int links = 0;
  while (!pending.empty()) {
    const fs::path element = pending.front();
    pending.pop_front();
    if (element.empty() || element == ".") continue;  // a trailing slash gives an empty element
    if (element == "..") {
      result = result.parent_path();  // result has no links left: its parent is the real one ("/" stays "/")
      continue;
    }
    const fs::path next = result / element;
    std::error_code error;
    const fs::file_status status = fs::symlink_status(next, error);
    if (error || !fs::is_symlink(status)) {  // a folder, a file, missing or not examinable: kept as written
      result = next;
      continue;
    }
    if (++links > kMaxLinks) throw InputError("'" + absolute.string() + "': too many symbolic links");
    const fs::path target = fs::read_symlink(next, error);
    if (error) {
      result = next;
      continue;
    }
    std::vector<fs::path> target_elements(target.begin(), target.end());
    auto first = target_elements.begin();
    if (target.is_absolute()) {
      result = target.root_path();
      ++first;
    }
    pending.insert(pending.begin(), first, target_elements.end());
  }
  return result;
}

bool isInsideFolder(const fs::path& path, const fs::path& root) {
  auto p = path.begin();
  for (const fs::path& element : root) {
    if (element.empty()) continue;
    while (p != path.end() && p->empty()) ++p;
    if (p == path.end() || *p != element) return false;
    ++p;
  }
  return true;
}

ConfinedPath confinePath(const FolderConfinement& confinement, const std::string& requested) {
  ConfinedPath out;
  if (requested.empty()) {
    out.refusal = "'': no path given: name a file or folder in the configured " + confinement.description;
    return out;
  }
  if (requested.find('\0') != std::string::npos) {
    out.refusal = outsideRefusal(confinement, requested);  // the OS would read another path than the one checked
    return out;
  }
  std::vector<fs::path> roots;
  for (const std::string& root : confinement.roots)
    if (fs::path(root).is_absolute()) {
      try {
        roots.push_back(resolvedPath(root));
      } catch (const InputError&) {  // a root in a link loop admits nothing
      }
    }
  if (roots.empty()) {
    out.refusal = "no " + confinement.description + " are configured: every path is refused";
    return out;
  }
  const fs::path given(requested);
  fs::path resolved;
  try {
    resolved = resolvedPath(given.is_absolute() ? given : roots.front() / given);
  } catch (const InputError&) {  // a link loop: refused as any outside path, whether inside or not
    out.refusal = outsideRefusal(confinement, requested);
    return out;
  }
  for (const fs::path& root : roots)
    if (isInsideFolder(resolved, root)) {
      out.inside = true;
      out.path = resolved.string();
      return out;
    }
  out.refusal = outsideRefusal(confinement, requested);
  return out;
}

std::string confinedPathOrThrow(const FolderConfinement& confinement, const std::string& requested) {
  ConfinedPath confined = confinePath(confinement, requested);
  if (!confined.inside) throw InputError(confined.refusal);
  return confined.path;
}

}  // namespace art2part
