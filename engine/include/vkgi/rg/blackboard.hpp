#pragma once
// Typed hand-off of graph handles between modules (skaarj's blackboard): the G-buffer module
// adds a GBufferData struct, the GI module gets it back by type. No string lookups, so a
// missing producer is a clear error at the consumer instead of a silent wrong resource.
#include <any>
#include <typeindex>
#include <unordered_map>

namespace vkgi::rg {

namespace detail {
// Reports a Blackboard::get of a type nobody added (defined in the engine library).
[[noreturn]] void missingBlackboardEntry(const char* typeName);
} // namespace detail

class Blackboard {
public:
    // Stores `value` (replacing any previous T) and returns the stored copy.
    template <typename T> T& add(T value) {
        std::any& slot = m_items[std::type_index(typeid(T))];
        slot = std::move(value);
        return *std::any_cast<T>(&slot);
    }
    // The stored T; a missing T is a programming error (a module ran before its producer).
    template <typename T> const T& get() const {
        const T* value = tryGet<T>();
        if (value == nullptr)
            detail::missingBlackboardEntry(typeid(T).name());
        return *value;
    }
    template <typename T> T& get() { return const_cast<T&>(static_cast<const Blackboard*>(this)->get<T>()); }
    // The stored T, or null.
    template <typename T> const T* tryGet() const {
        auto it = m_items.find(std::type_index(typeid(T)));
        return it == m_items.end() ? nullptr : std::any_cast<T>(&it->second);
    }
    template <typename T> bool has() const { return tryGet<T>() != nullptr; }
    void clear() { m_items.clear(); }

private:
    std::unordered_map<std::type_index, std::any> m_items;
};

} // namespace vkgi::rg
