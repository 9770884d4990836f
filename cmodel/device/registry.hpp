// The device backends by name (docs/architecture.md "Layers"): this build's backends,
// each with its own command-line options, and make_device. A host program needs only
// this header of the device layer: with it come the Device interface (device.hpp) and a
// frame on a device (render_frame.hpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "fp/format.hpp"
#include "memory/memory_image.hpp"
#include "render/render.hpp"
#include "rpu/spec.hpp"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace rpu::device {

// What every device backend takes from the host program.
struct DeviceOptions {
  std::uint64_t watchdog = 50'000'000;  // instructions one thread may retire for one pixel
  int host_threads = 0;                 // the functional backend's (0: all cores)
  IsectMode isect = IsectMode::kWoop;   // the image's test (the rtl backend's chip is built for one)
};

// A file a backend's options will write, for the check that no output overwrites
// another or an input: the option, its path, the file types it takes.
struct BackendOutput {
  std::string option;
  std::filesystem::path path;
  std::vector<std::string> extensions;
};

// A device backend as `rpu render --backend` offers it: its own options (bound to this
// object), their checks, the device it makes and what it writes after the frame. It
// outlives the devices it makes: with its outputs asked for, they call back into it.
class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::string_view name() const = 0;
  // Adds its own options to `command`, each one's help starting "<name> backend:".
  virtual void add_options(CLI::App& command);
  // Checks its options against the run before any work (rpu::Error); `select` is the
  // --select given.
  virtual void check(const RenderSettings& settings, std::string_view select) const;
  // The files its options will write.
  virtual std::vector<BackendOutput> outputs() const;
  // rpu::Error unless a device of this configuration, format and intersection test can
  // be made (the rtl backend runs only the chips it was built with); what a sweep checks
  // of each point before it runs any.
  virtual void check_runs(const spec::HardwareConfig& config, fp::Format format, IsectMode isect) const;
  virtual std::unique_ptr<Device> make(const spec::HardwareConfig& config, fp::Format format,
                                       const DeviceOptions& options) = 0;
  // After a frame on the device it made: writes its own outputs and prints its lines for
  // the terminal.
  virtual void finish(const DeviceStats& stats);
};

// This build's backends, in the order `--backend` lists them: functional, cycle, and rtl
// where the RTL is built (RPU_RTL).
class Registry {
 public:
  Registry();

  std::vector<std::string> names() const;
  // The backend `name`, or null.
  Backend* find(std::string_view name) const;
  // Every backend's own options onto `command`.
  void add_options(CLI::App& command);
  // rpu::Error naming the options of another backend than `chosen` that the command
  // line gave, and their backend ("--heatmap needs --backend cycle").
  void refuse_others(std::string_view chosen) const;

 private:
  struct Entry {
    std::unique_ptr<Backend> backend;
    std::vector<const CLI::Option*> options;  // its own, once added
  };
  std::vector<Entry> entries_;
};

// A device of the backend `name` with its own options' defaults; rpu::Error naming this
// build's backends for an unknown name.
std::unique_ptr<Device> make_device(std::string_view name, const spec::HardwareConfig& config, fp::Format format,
                                    const DeviceOptions& options = {});

}  // namespace rpu::device
