#pragma once
// Forward declarations, so headers that only pass the registry around need not include it.
#include <cstdint>

namespace ikebana::ecs {

struct Entity;
class Registry;
class CommandBuffer;
struct AccessMask;
class SparseSet;
template <typename T>
class Storage;
template <typename... T>
struct Exclude;
struct ChildOf;
struct Children;

} // namespace ikebana::ecs
