#pragma once
// PlcImage: the process image of the TwinCAT PLC emulator (`hybridtest bench --protocol
// ads`): the profile's variables for n actuators (ads_profile.h), laid out one after another
// in the PLC data area (index group 0x4040, each at its own index offset), with their symbol
// entries and the handles clients took. It answers the index-group services of a PLC:
//
//   0xF003 ReadWrite name → handle (read length 4: the handle; larger: handle, size, type)
//   0xF005 Read/Write by handle        0xF006 Write: release a handle
//   0xF004 ReadWrite name → value      0xF009 ReadWrite name → symbol entry (SymbolInfo)
//   0x4040 Read/Write by index offset  (the data area itself)
//
// Symbol names are matched without regard to case, as TwinCAT does. An unknown name or
// handle is ADS error 0x710, an access outside a variable 0x705 (size) or 0x703 (offset), an
// unknown index group 0x702. The sum commands and the PLC's cycle are the server's
// (ads_server.h). Not thread-safe: the server's one thread owns it.
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/ads/ads_codec.h"
#include "hybridtest/transfer/ads/ads_profile.h"

namespace hybridtest::transfer::ads {

class PlcImage {
 public:
  explicit PlcImage(const AdsProfile& profile);

  // The variables by role (bench units, as the PLC holds them).
  std::vector<double> Reals(Role role) const;
  void SetReals(Role role, std::span<const double> values);
  std::uint32_t Udint(Role role) const;
  void SetUdint(Role role, std::uint32_t value);
  bool Bool(Role role) const;
  void SetBool(Role role, bool value);

  // The index-group services above. `owner` identifies the connection that takes a handle
  // (ReleaseAll(owner) frees them when it goes). Each returns the ADS result (0: done).
  DataResponse Read(std::uint32_t group, std::uint32_t offset, std::uint32_t length) const;
  std::uint32_t Write(std::uint32_t group, std::uint32_t offset,
                      std::span<const std::uint8_t> data, int owner);
  DataResponse ReadWrite(std::uint32_t group, std::uint32_t offset, std::uint32_t read_length,
                         std::span<const std::uint8_t> data, int owner);
  void ReleaseAll(int owner);

  const SymbolInfo& symbol(Role role) const { return symbols_[role]; }
  std::size_t handles() const { return handles_.size(); }  // open handles of every client

 private:
  struct Handle {
    Role role;
    int owner;
  };
  // The role whose variable holds [offset, offset + length) of the data area; kNumRoles if none.
  Role At(std::uint32_t offset, std::uint32_t length) const;
  Role ByName(const std::string& name) const;  // kNumRoles if unknown

  std::vector<SymbolInfo> symbols_;   // by Role
  std::vector<std::uint8_t> memory_;  // the data area
  std::map<std::uint32_t, Handle> handles_;
  std::uint32_t next_handle_ = 0x1000;
};

}  // namespace hybridtest::transfer::ads
