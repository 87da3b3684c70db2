#include "hairlod/io/hair_file.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <new>
#include <random>
#include <string>
#include <system_error>

#include <unistd.h>

#include "hairlod/core/error.h"
#include "hairlod/io/ct2hair_bin.h"
#include "hairlod/io/cyhair.h"
#include "hairlod/io/ply_hair.h"
#include "hairlod/io/tfx.h"
#include "hairlod/io/usc_data.h"

namespace hairlod::io {

namespace {

constexpr HairFormatInfo formats[] = {
    {HairFormat::CyHair, ".hair", "Cem Yuksel's cyHair", true},
    {HairFormat::UscData, ".data", "USC-HairSalon strands", true},
    {HairFormat::Ct2HairBin, ".bin", "CT2Hair strands", false},
    {HairFormat::Ply, ".ply", "PLY hair (hairutil)", false},
    {HairFormat::TressFx, ".tfx", "AMD TressFX", false},
};

const HairFormatInfo& format_info(HairFormat format) {
    return *std::find_if(std::begin(formats), std::end(formats),
                         [format](const HairFormatInfo& info) { return info.format == format; });
}

std::string extension_list(bool writable_only) {
    std::string list;
    for (const HairFormatInfo& info : formats) {
        if (writable_only && !info.writable) continue;
        if (!list.empty()) list += ", ";
        list += info.extension;
    }
    return list;
}

std::string path_prefix(const std::filesystem::path& path) { return path.string() + ": "; }

std::vector<std::byte> read_whole_file(const std::filesystem::path& path) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error))
        throw Error(error || !std::filesystem::exists(path, error) ? "no such file"
                                                                   : "not a regular file");
    const std::uintmax_t size = std::filesystem::file_size(path, error);
    if (error) throw Error("cannot get the file size: " + error.message());
    std::ifstream stream(path, std::ios::binary);
    if (!stream) throw Error("cannot open the file for reading");
    std::vector<std::byte> bytes;
    try {
        bytes.resize(size);
    } catch (const std::bad_alloc&) {
        throw Error("the file has " + std::to_string(size) + " bytes, more than fit in memory");
    }
    stream.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
    if (static_cast<std::uintmax_t>(stream.gcount()) != size)
        throw Error("read " + std::to_string(stream.gcount()) + " of " + std::to_string(size) +
                    " bytes; the file changed or cannot be read");
    return bytes;
}

// A name in the same directory (so the rename stays on one file system) that no other writer
// picks: hidden, with the process id and a random token, `.NAME.hairlod-PID-TOKEN.tmp`. The Python
// package names its temporaries the same way (addon/hairlod/atomic_output.py), so a later write of
// the same target removes the ones a killed process left.
std::filesystem::path temporary_path_for(const std::filesystem::path& path) {
    std::random_device random;
    const uint64_t token = (uint64_t{random()} << 32) ^ random();
    std::string name(1, '.');
    name += path.filename().string();
    name += ".hairlod-" + std::to_string(::getpid()) + "-";
    constexpr char hex[] = "0123456789abcdef";
    for (int shift = 60; shift >= 0; shift -= 4) name += hex[(token >> shift) & 0xf];
    name += ".tmp";
    return path.parent_path() / name;
}

// Errors name the user's path, not the temporary one.
void write_file_atomically(const std::filesystem::path& path, std::span<const std::byte> bytes) {
    const std::filesystem::path temporary = temporary_path_for(path);
    try {
        {
            std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
            if (!stream) throw Error("cannot create the file (is its folder there and writable?)");
            stream.write(reinterpret_cast<const char*>(bytes.data()),
                         static_cast<std::streamsize>(bytes.size()));
            stream.close();
            if (!stream) throw Error("writing failed (is the disk full?)");
        }
        std::error_code error;
        std::filesystem::rename(temporary, path, error);
        if (error) throw Error("cannot replace it with the finished file: " + error.message());
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw;
    }
}

}  // namespace

std::span<const HairFormatInfo> hair_formats() { return formats; }

HairFormat hair_format_from_path(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    for (const HairFormatInfo& info : formats)
        if (info.extension == extension) return info.format;
    throw Error(path_prefix(path) + "unknown hair file extension '" + path.extension().string() +
                "'; supported: " + extension_list(false));
}

HairFileContents read_hair_bytes(HairFormat format, std::span<const std::byte> bytes,
                                 const ReadOptions& options) {
    switch (format) {
        case HairFormat::CyHair: return {read_cyhair(bytes).strands, 0};
        case HairFormat::UscData: {
            StrandListFile file = read_usc_data(bytes, options);
            return {std::move(file.strands), file.skipped_strands};
        }
        case HairFormat::Ct2HairBin: {
            StrandListFile file = read_ct2hair_bin(bytes, options);
            return {std::move(file.strands), file.skipped_strands};
        }
        case HairFormat::Ply: return {read_ply_hair(bytes, options), 0};
        case HairFormat::TressFx: return {read_tfx(bytes, options), 0};
    }
    throw Error("unknown hair format");
}

std::vector<std::byte> write_hair_bytes(HairFormat format, const StrandSet& strands) {
    switch (format) {
        case HairFormat::CyHair: return write_cyhair(strands);
        case HairFormat::UscData: return write_usc_data(strands);
        case HairFormat::Ct2HairBin:
        case HairFormat::Ply:
        case HairFormat::TressFx: break;
    }
    throw Error(std::string("writing ") + std::string(format_info(format).extension) +
                " is not supported; hairlod writes " + extension_list(true));
}

HairFileContents read_hair_file(const std::filesystem::path& path, const ReadOptions& options) {
    const HairFormat format = hair_format_from_path(path);
    try {
        return read_hair_bytes(format, read_whole_file(path), options);
    } catch (const Error& error) {
        throw Error(path_prefix(path) + error.what());
    }
}

void write_hair_file(const std::filesystem::path& path, const StrandSet& strands) {
    const HairFormat format = hair_format_from_path(path);
    try {
        write_file_atomically(path, write_hair_bytes(format, strands));
    } catch (const Error& error) {
        throw Error(path_prefix(path) + error.what());
    }
}

}  // namespace hairlod::io
