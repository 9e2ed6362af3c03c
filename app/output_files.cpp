#include "app/output_files.hpp"

#include "app/output_stream.hpp"

#include <fmt/format.h>

#include <map>
#include <memory>

namespace thermnet::app {
namespace {

/// "OPTION 'PATH'" for messages.
std::string describe(const NamedOutput& o) {
  return fmt::format("{} '{}'", o.option, o.path);
}

} // namespace

void check_outputs(const std::vector<NamedOutput>& outputs, const std::vector<NamedInput>& inputs) {
  std::map<std::string, const NamedInput*> input_files;
  for (const auto& in : inputs)
    if (std::string id = regular_file_identity(in.path); !id.empty()) input_files.emplace(id, &in);
  std::map<std::string, const NamedOutput*> seen;
  for (const auto& out : outputs) {
    if (out.path.empty()) continue;
    const OutputTarget t = resolve_output(out.path, out.follow);
    if (t.kind == OutputTarget::Kind::stream) continue; // writing a device or FIFO destroys nothing
    const std::string id = t.identity();
    if (auto it = input_files.find(id); it != input_files.end())
      throw OutputError(fmt::format("{} would overwrite {} '{}', an input of this run; write "
                                    "to another file",
                                    describe(out), it->second->role, it->second->path));
    if (auto [it, fresh] = seen.emplace(id, &out); !fresh)
      throw OutputError(fmt::format("{} and {} are the same file; give each output its own file",
                                    describe(*it->second), describe(out)));
  }
}

void write_output_file(const std::string& path, const std::string& content) {
  write_output_files({OutputFile{path, content}});
}

void write_output_files(const std::vector<OutputFile>& files) {
  std::vector<NamedOutput> named;
  for (const auto& f : files)
    named.push_back({"output", f.path, f.follow});
  check_outputs(named, {});
  std::vector<std::unique_ptr<OutputStream>> streams;
  for (const auto& f : files)
    streams.push_back(std::make_unique<OutputStream>(f.path, f.follow));
  std::vector<OutputStream*> all;
  for (std::size_t i = 0; i < files.size(); ++i) {
    streams[i]->write(files[i].content);
    all.push_back(streams[i].get());
  }
  commit(all);
}

} // namespace thermnet::app
