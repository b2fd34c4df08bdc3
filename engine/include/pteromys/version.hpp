#pragma once
namespace pteromys {
inline constexpr const char* kVersion = "0.1.0";
}
