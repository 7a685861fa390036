#include "opencl/scene_upload.h"

#include <algorithm>
#include <string>
#include <type_traits>

#include "core/memory_limits.h"
#include "render/device_error.h"

namespace ray::engine {

namespace {

std::string mebibytes(uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

// A table of the packed scene as a device buffer. A CPU device reads the host's table in
// place (CL_MEM_USE_HOST_PTR: PoCL then neither copies nor allocates it), so the table must
// stay unchanged and alive while the buffer lives (DeviceSlot::releaseScene). Other devices
// get a copy in their memory. OpenCL refuses zero-sized buffers; an empty table gets one
// unused element.
template <typename T>
cl::Buffer uploadBuffer(const cl::Context& context, const std::vector<T>& data, bool inPlace) {
    static const T placeholder{};
    const void* source = data.empty() ? static_cast<const void*>(&placeholder) : data.data();
    size_t bytes = std::max<size_t>(1, data.size()) * sizeof(T);
    const cl_mem_flags flags = CL_MEM_READ_ONLY | (inPlace ? CL_MEM_USE_HOST_PTR : CL_MEM_COPY_HOST_PTR);
    return cl::Buffer(context, flags, bytes, const_cast<void*>(source));
}

}  // namespace

void checkDeviceLimits(const OpenClDevice& device, const KernelVariant& variant, const PackedScene& packed,
                       size_t tileBytes) {
    const std::string advice = "; use a smaller scene or image, another device (ray --list-devices), or --device ref";
    auto checkAllocation = [&](const char* what, size_t bytes) {
        if (bytes > device.maxAllocation)
            throw DeviceError("the scene's " + std::string(what) + " need a " + mebibytes(bytes) +
                              " buffer, more than the " + mebibytes(device.maxAllocation) + " " +
                              device.description() + " allows in one allocation" + advice);
    };
    uint64_t sceneBytes = 0;
    packed.forEachBuffer([&](const auto& table, SceneBufferName name) {
        if (!variant.reads(name)) return;
        checkAllocation(name.what, table.size() * sizeof(table[0]));
        sceneBytes += table.size() * sizeof(table[0]);
    });
    checkAllocation("tile", tileBytes);
    // Each launch in flight has its colors and ray counts: two buffers of tileBytes.
    uint64_t total = sceneBytes + 2 * kTilesInFlight * uint64_t(tileBytes);
    if (total > device.globalMemory)
        throw DeviceError("the scene needs " + mebibytes(total) + " of device memory, more than the " +
                          mebibytes(device.globalMemory) + " of " + device.description() + advice);
    // On the host: a tile's buffers read back, and on a CPU device its tile outputs too (it
    // reads the scene's tables where they are: uploadBuffer).
    const uint64_t outputs = 2 * kTilesInFlight * uint64_t(tileBytes);
    uint64_t hostBytes = 2 * uint64_t(tileBytes) + (device.isCpu ? outputs : 0);
    if (auto shortfall = hostMemoryShortfall(hostBytes))
        throw DeviceError("rendering on " + device.description() + " " + *shortfall + " on the host" + advice);
}

bool uploadScene(DeviceSlot& slot, const std::shared_ptr<const PackedScene>& packed) {
    // The test hook copyScene: Oclgrind's --uninitialized takes a CL_MEM_USE_HOST_PTR buffer
    // for never written (tests/oclgrind.sh); a copy holds the same bytes.
    const bool inPlace = slot.device.isCpu && !slot.hooks.copyScene;
    size_t next = 0;
    bool uploadedAny = false;
    packed->forEachBuffer([&](const auto& table, SceneBufferName name) {
        const size_t i = next++;
        const bool current = slot.sceneBuffers[i]() && slot.bufferVersions[i] == packed->versions[i];
        // A table an edit kept is the same bytes in the new packing: a device reading it in
        // place moves onto the new packing's (a buffer made, nothing copied), so that the old
        // packing is freed rather than held beside the new one for the rest of the session.
        if (current && (!inPlace || slot.bufferOwners[i] == packed)) return;
        slot.sceneBuffers[i] = cl::Buffer();  // before its table's owner may go
        slot.bufferOwners[i].reset();
        const std::remove_cvref_t<decltype(table)> unread;  // a table the device's kernel never reads
        slot.sceneBuffers[i] = uploadBuffer(slot.context, slot.variant.reads(name) ? table : unread, inPlace);
        slot.bufferVersions[i] = packed->versions[i];
        // A copy is the device's own: the host's table need not outlive it.
        if (inPlace) slot.bufferOwners[i] = packed;
        uploadedAny = uploadedAny || !current;
    });
    slot.uploaded = packed;
    return uploadedAny;
}

}  // namespace ray::engine
