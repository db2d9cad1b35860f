#pragma once
// A DIY force-feedback device emulated inside the program, behind the real HID transport (its I/O
// thread, mailbox and close), for trying and testing the whole force chain without hardware: a state
// report every millisecond as the firmware sends them, the handle 60 mm above the workspace's centre
// for half a second and then sinking to 20 mm below it (a hand resting on it, pressing what is there), and every force report it is written appended to a log file as one line,
// `force FX FY FZ` (newtons; `refused` for a report that does not decode). `--left emulated-diy:LOG`.
#include <memory>
#include <string>

#include "engine/core/result.hpp"
#include "engine/devices/hid_transport.hpp"

namespace ikebana::devices {

[[nodiscard]] Result<std::unique_ptr<HidTransport>> open_emulated_diy(const std::string& log_path);

} // namespace ikebana::devices
