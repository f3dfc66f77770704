// The device requirements declared once for DeviceBuilder and embedding hosts
// (docs/embedding.md "The device vkgi needs"): no device is created here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <iterator>

#include "vkgi/context.hpp"

namespace vkgi {
namespace {

// The optional core features vkgi uses when the device has them; every other VkPhysicalDeviceFeatures
// member must stay off whatever the device supports.
constexpr VkBool32 VkPhysicalDeviceFeatures::* kOptional[] = {
    &VkPhysicalDeviceFeatures::fragmentStoresAndAtomics, &VkPhysicalDeviceFeatures::vertexPipelineStoresAndAtomics,
    &VkPhysicalDeviceFeatures::geometryShader,           &VkPhysicalDeviceFeatures::shaderStorageImageExtendedFormats,
    &VkPhysicalDeviceFeatures::samplerAnisotropy,        &VkPhysicalDeviceFeatures::depthClamp,
};

VkPhysicalDeviceFeatures allSupported() {
    VkPhysicalDeviceFeatures f;
    VkBool32* flags = reinterpret_cast<VkBool32*>(&f);
    std::fill(flags, flags + sizeof(f) / sizeof(VkBool32), VK_TRUE);
    return f;
}

TEST(DeviceFeatureChain, LinksTheThreeCoreVersionsInOrder) {
    const DeviceFeatureChain chain(VkPhysicalDeviceFeatures{});
    EXPECT_EQ(chain.features.sType, VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
    EXPECT_EQ(chain.features.pNext, &chain.v13);
    EXPECT_EQ(chain.v13.sType, VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES);
    EXPECT_EQ(chain.v13.pNext, &chain.v12);
    EXPECT_EQ(chain.v12.sType, VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
    EXPECT_EQ(chain.v12.pNext, &chain.v11);
    EXPECT_EQ(chain.v11.sType, VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES);
    EXPECT_EQ(chain.v11.pNext, nullptr); // where a host chains its own structures
}

TEST(DeviceFeatureChain, EnablesExactlyTheRequiredFeatures) {
    const DeviceFeatureChain chain(VkPhysicalDeviceFeatures{});
    EXPECT_EQ(chain.v13.synchronization2, VK_TRUE);
    EXPECT_EQ(chain.v13.dynamicRendering, VK_TRUE);
    EXPECT_EQ(chain.v13.maintenance4, VK_TRUE);
    EXPECT_EQ(chain.v12.hostQueryReset, VK_TRUE);
    EXPECT_EQ(chain.v12.scalarBlockLayout, VK_TRUE);
    EXPECT_EQ(chain.v11.multiview, VK_TRUE);
    // Nothing else of the 1.1-1.3 structures: count the VkBool32 members that are on.
    auto countOn = [](const auto& s) {
        const size_t header = offsetof(VkPhysicalDeviceVulkan11Features, storageBuffer16BitAccess);
        const auto* flags = reinterpret_cast<const VkBool32*>(reinterpret_cast<const char*>(&s) + header);
        size_t on = 0;
        for (size_t i = 0; i < (sizeof(s) - header) / sizeof(VkBool32); ++i)
            on += flags[i] == VK_TRUE;
        return on;
    };
    EXPECT_EQ(countOn(chain.v13), 3u);
    EXPECT_EQ(countOn(chain.v12), 2u);
    EXPECT_EQ(countOn(chain.v11), 1u);
    const VkPhysicalDeviceFeatures none{};
    EXPECT_EQ(std::memcmp(&chain.features.features, &none, sizeof(none)), 0)
        << "a device without the optional features gets none of them";
}

TEST(DeviceFeatureChain, TakesTheOptionalFeaturesOnlyWhereSupported) {
    const DeviceFeatureChain all(allSupported());
    VkPhysicalDeviceFeatures expected{};
    for (auto member : kOptional)
        expected.*member = VK_TRUE;
    EXPECT_EQ(std::memcmp(&all.features.features, &expected, sizeof(expected)), 0)
        << "only the optional features vkgi uses, even where the device has every feature";
    for (auto member : kOptional) {
        VkPhysicalDeviceFeatures one{};
        one.*member = VK_TRUE;
        const DeviceFeatureChain chain(one);
        EXPECT_EQ(std::memcmp(&chain.features.features, &one, sizeof(one)), 0);
    }
}

TEST(DeviceFeatureChain, NamesPushDescriptorAsTheRequiredExtension) {
    ASSERT_EQ(std::size(kRequiredDeviceExtensions), 1u);
    EXPECT_STREQ(kRequiredDeviceExtensions[0], VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);
}

} // namespace
} // namespace vkgi
