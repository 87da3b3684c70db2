#include "hairlod/io/ply_hair.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hairlod/core/error.h"
#include "hairlod/io/byte_reader.h"
#include "require_finite.h"

namespace hairlod::io {

namespace {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct PlyTypeName {
    std::string_view name;
    PlyType type;
};

constexpr PlyTypeName ply_type_names[] = {
    {"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
    {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},     {"int16", PlyType::Int16},
    {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
    {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
    {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
    {"float64", PlyType::Float64},
};

size_t type_size(PlyType type) {
    switch (type) {
        case PlyType::Int8:
        case PlyType::UInt8: return 1;
        case PlyType::Int16:
        case PlyType::UInt16: return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
    }
    return 0;
}

bool is_integer(PlyType type) { return type != PlyType::Float32 && type != PlyType::Float64; }

// Whether an ascii value is a whole number in the range of an integer type.
bool fits_integer_type(double value, PlyType type) {
    const auto fits = [value]<typename T>(T) {
        return value == std::floor(value) && value >= std::numeric_limits<T>::min() &&
               value <= std::numeric_limits<T>::max();
    };
    switch (type) {
        case PlyType::Int8: return fits(int8_t{});
        case PlyType::UInt8: return fits(uint8_t{});
        case PlyType::Int16: return fits(int16_t{});
        case PlyType::UInt16: return fits(uint16_t{});
        case PlyType::Int32: return fits(int32_t{});
        case PlyType::UInt32: return fits(uint32_t{});
        case PlyType::Float32:
        case PlyType::Float64: return true;
    }
    return false;
}

// What the reader does with a property's values.
enum class Role { Ignore, X, Y, Z, Red, Green, Blue, Radius, StrandSize };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Float32;
    bool is_list = false;
    PlyType list_size_type = PlyType::UInt8;
    Role role = Role::Ignore;
    double scale = 1.0;  // value * scale + shift is what the role stores
    double shift = 0.0;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
    size_t body_offset = 0;
};

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        const size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
        if (i > start) words.push_back(line.substr(start, i - start));
    }
    return words;
}

PlyType parse_type(std::string_view name, size_t line_number) {
    for (const PlyTypeName& entry : ply_type_names)
        if (entry.name == name) return entry.type;
    throw Error("header line " + std::to_string(line_number) + ": unknown property type '" +
                std::string(name) + "'");
}

uint64_t parse_element_count(std::string_view text, size_t line_number) {
    uint64_t count = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), count);
    if (error != std::errc() || end != text.data() + text.size())
        throw Error("header line " + std::to_string(line_number) + ": element count '" +
                    std::string(text) + "' is not a non-negative integer");
    return count;
}

PlyHeader parse_header(std::string_view text) {
    PlyHeader header;
    bool has_format = false;
    size_t line_start = 0;
    for (size_t line_number = 1;; ++line_number) {
        const size_t newline = text.find('\n', line_start);
        if (newline == std::string_view::npos) throw Error("header has no end_header line");
        std::string_view line = text.substr(line_start, newline - line_start);
        line_start = newline + 1;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        const std::string where = "header line " + std::to_string(line_number) + ": ";

        if (line_number == 1) {
            if (line != "ply") throw Error("not a PLY file: it does not start with \"ply\"");
            continue;
        }
        const std::vector<std::string_view> words = split_words(line);
        if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
        if (words[0] == "end_header") break;
        if (words[0] == "format") {
            if (words.size() != 3 || words[2] != "1.0")
                throw Error(where + "expected 'format <type> 1.0'");
            if (words[1] == "ascii")
                header.format = PlyFormat::Ascii;
            else if (words[1] == "binary_little_endian")
                header.format = PlyFormat::BinaryLittleEndian;
            else if (words[1] == "binary_big_endian")
                header.format = PlyFormat::BinaryBigEndian;
            else
                throw Error(where + "unknown format '" + std::string(words[1]) + "'");
            has_format = true;
        } else if (words[0] == "element") {
            if (words.size() != 3) throw Error(where + "expected 'element <name> <count>'");
            header.elements.push_back(
                {std::string(words[1]), parse_element_count(words[2], line_number), {}});
        } else if (words[0] == "property") {
            if (header.elements.empty()) throw Error(where + "property before any element");
            PlyProperty property;
            if (words.size() == 5 && words[1] == "list") {
                property.is_list = true;
                property.list_size_type = parse_type(words[2], line_number);
                property.type = parse_type(words[3], line_number);
                property.name = words[4];
                if (!is_integer(property.list_size_type))
                    throw Error(where + "list size type must be an integer type");
            } else if (words.size() == 3) {
                property.type = parse_type(words[1], line_number);
                property.name = words[2];
            } else {
                throw Error(where + "expected 'property <type> <name>' or "
                                    "'property list <size type> <type> <name>'");
            }
            std::vector<PlyProperty>& properties = header.elements.back().properties;
            for (const PlyProperty& other : properties)
                if (other.name == property.name)
                    throw Error(where + "element '" + header.elements.back().name +
                                "' has property '" + property.name + "' twice");
            properties.push_back(std::move(property));
        } else {
            throw Error(where + "unknown keyword '" + std::string(words[0]) + "'");
        }
    }
    if (!has_format) throw Error("header has no format line");
    header.body_offset = line_start;
    return header;
}

// Reads property values from the body, in binary or as ascii text.
class PlyBodyReader {
public:
    PlyBodyReader(std::span<const std::byte> body, PlyFormat format)
        : binary_(body, format == PlyFormat::BinaryBigEndian ? ByteOrder::BigEndian
                                                             : ByteOrder::LittleEndian),
          text_(reinterpret_cast<const char*>(body.data()), body.size()),
          ascii_(format == PlyFormat::Ascii) {}

    // Bytes available to values: what is left, plus in ascii the separator the last value lacks.
    size_t value_budget() const {
        return ascii_ ? text_.size() - text_position_ + 1 : binary_.remaining();
    }

    // The fewest bytes one value can take: its binary size, or one character and a separator.
    size_t min_value_bytes(PlyType type) const { return ascii_ ? 2 : type_size(type); }

    double read_value(PlyType type) {
        if (ascii_) return parse_ascii_value(type);
        switch (type) {
            case PlyType::Int8: return binary_.read<int8_t>("char value");
            case PlyType::UInt8: return binary_.read<uint8_t>("uchar value");
            case PlyType::Int16: return binary_.read<int16_t>("short value");
            case PlyType::UInt16: return binary_.read<uint16_t>("ushort value");
            case PlyType::Int32: return binary_.read<int32_t>("int value");
            case PlyType::UInt32: return binary_.read<uint32_t>("uint value");
            case PlyType::Float32: return binary_.read<float>("float value");
            case PlyType::Float64: return binary_.read<double>("double value");
        }
        return 0.0;
    }

    // A list's item count: a non-negative integer whose items fit in what is left of the file.
    uint64_t read_list_size(PlyType size_type, PlyType item_type) {
        const double size = read_value(size_type);
        if (size < 0.0) throw Error("list size " + std::to_string(size) + " is negative");
        const auto count = static_cast<uint64_t>(size);
        if (count > value_budget() / min_value_bytes(item_type))
            throw Error("list claims " + std::to_string(count) + " items but only " +
                        std::to_string(value_budget()) + " bytes are left");
        return count;
    }

    void skip_values(PlyType type, uint64_t count) {
        if (!ascii_) {
            binary_.skip(count * type_size(type), "list items");
            return;
        }
        for (uint64_t i = 0; i < count; ++i) parse_ascii_value(type);
    }

    void expect_end() {
        if (ascii_) {
            skip_whitespace();
            if (text_position_ != text_.size())
                throw Error("unexpected text after the last element at body offset " +
                            std::to_string(text_position_));
        } else if (binary_.remaining() != 0) {
            throw Error(std::to_string(binary_.remaining()) +
                        " unexpected bytes after the last element");
        }
    }

private:
    static bool is_space(char c) {
        return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
    }

    void skip_whitespace() {
        while (text_position_ < text_.size() && is_space(text_[text_position_])) ++text_position_;
    }

    double parse_ascii_value(PlyType type) {
        skip_whitespace();
        size_t end = text_position_;
        while (end < text_.size() && !is_space(text_[end])) ++end;
        if (end == text_position_) throw Error("file ends before the last value of the body");
        const std::string_view token = text_.substr(text_position_, end - text_position_);
        // from_chars rejects a leading '+', which some writers emit.
        const std::string_view digits = token.front() == '+' ? token.substr(1) : token;
        double value = 0.0;
        const auto [parsed_end, error] =
            std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (error != std::errc() || parsed_end != digits.data() + digits.size() ||
            !fits_integer_type(value, type))
            throw Error("'" + std::string(token) + "' at body offset " +
                        std::to_string(text_position_) + " is not a valid " +
                        (is_integer(type) ? "integer of its type" : "number"));
        text_position_ = end;
        return value;
    }

    ByteReader binary_;
    std::string_view text_;
    size_t text_position_ = 0;
    bool ascii_;
};

PlyElement* find_element(PlyHeader& header, std::string_view name) {
    for (PlyElement& element : header.elements)
        if (element.name == name) return &element;
    return nullptr;
}

PlyProperty* find_property(PlyElement& element, std::string_view name) {
    for (PlyProperty& property : element.properties)
        if (property.name == name) return &property;
    return nullptr;
}

// Gives a scalar property a role; throws if it is a list.
void assign_role(PlyElement& element, PlyProperty& property, Role role, double scale = 1.0,
                 double shift = 0.0) {
    if (property.is_list)
        throw Error("property '" + property.name + "' of element '" + element.name +
                    "' must be a scalar, not a list");
    property.role = role;
    property.scale = scale;
    property.shift = shift;
}

// Colour channels: uchar scaled to [0, 1], floats as stored.
void assign_color_role(PlyElement& vertex, PlyProperty& property, Role role) {
    if (property.type == PlyType::UInt8)
        assign_role(vertex, property, role, 1.0 / 255.0);
    else if (property.type == PlyType::Float32 || property.type == PlyType::Float64)
        assign_role(vertex, property, role);
    else
        throw Error("colour property '" + property.name + "' must be uchar, float or double");
}

struct VertexRoles {
    bool has_color = false;
    bool has_radius = false;
};

VertexRoles assign_vertex_roles(PlyElement& vertex) {
    const std::pair<const char*, Role> coordinates[] = {{"x", Role::X}, {"y", Role::Y}, {"z", Role::Z}};
    for (const auto& [name, role] : coordinates) {
        PlyProperty* property = find_property(vertex, name);
        if (!property) throw Error("element 'vertex' has no property '" + std::string(name) + "'");
        assign_role(vertex, *property, role);
    }
    VertexRoles roles;
    PlyProperty* red = find_property(vertex, "red");
    PlyProperty* green = find_property(vertex, "green");
    PlyProperty* blue = find_property(vertex, "blue");
    if (red || green || blue) {
        if (!(red && green && blue))
            throw Error("element 'vertex' needs all of red, green, blue or none of them");
        assign_color_role(vertex, *red, Role::Red);
        assign_color_role(vertex, *green, Role::Green);
        assign_color_role(vertex, *blue, Role::Blue);
        roles.has_color = true;
    }
    // Thickness and width are diameters.
    const std::pair<const char*, double> radius_properties[] = {
        {"radius", 1.0}, {"thickness", 0.5}, {"width", 0.5}};
    for (const auto& [name, scale] : radius_properties) {
        if (PlyProperty* property = find_property(vertex, name)) {
            assign_role(vertex, *property, Role::Radius, scale);
            roles.has_radius = true;
            break;
        }
    }
    return roles;
}

void assign_strand_role(PlyElement& strand) {
    // nsegs counts segments, so a strand has nsegs + 1 points.
    const std::pair<const char*, double> size_properties[] = {
        {"nsegs", 1.0}, {"nverts", 0.0}, {"vertex_count", 0.0}};
    for (const auto& [name, shift] : size_properties) {
        if (PlyProperty* property = find_property(strand, name)) {
            if (!is_integer(property->type))
                throw Error("property '" + property->name + "' of element 'strand' must be an integer");
            assign_role(strand, *property, Role::StrandSize, 1.0, shift);
            return;
        }
    }
    throw Error("element 'strand' has none of the properties nsegs, nverts, vertex_count");
}

// Rejects element counts the body is too small for, before anything is allocated.
void check_counts_against_body(const PlyHeader& header, const PlyBodyReader& body) {
    uint64_t min_body_bytes = 0;
    for (const PlyElement& element : header.elements) {
        uint64_t min_row_bytes = 0;
        for (const PlyProperty& property : element.properties)
            min_row_bytes += body.min_value_bytes(property.is_list ? property.list_size_type
                                                                   : property.type);
        if (min_row_bytes == 0) continue;
        if (element.count > (body.value_budget() - min_body_bytes) / min_row_bytes)
            throw Error("header claims " + std::to_string(element.count) + " " + element.name +
                        " elements but only " + std::to_string(body.value_budget()) +
                        " bytes follow the header");
        min_body_bytes += element.count * min_row_bytes;
    }
}

}  // namespace

StrandSet read_ply_hair(std::span<const std::byte> bytes, const ReadOptions& options) {
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    PlyHeader header = parse_header(text);

    PlyElement* vertex = find_element(header, "vertex");
    if (!vertex) throw Error("file has no 'vertex' element");
    PlyElement* strand = find_element(header, "strand");
    if (!strand) throw Error("file has no 'strand' element");
    const VertexRoles vertex_roles = assign_vertex_roles(*vertex);
    assign_strand_role(*strand);

    PlyBodyReader body(bytes.subspan(header.body_offset), header.format);
    check_counts_against_body(header, body);

    const auto vertex_count = static_cast<size_t>(vertex->count);
    std::vector<glm::vec3> points(vertex_count);
    std::vector<float> radius(vertex_roles.has_radius ? vertex_count : 0);
    std::vector<float> color(vertex_roles.has_color ? 3 * vertex_count : 0);
    std::vector<int64_t> strand_sizes(static_cast<size_t>(strand->count));
    uint64_t strand_points = 0;

    for (const PlyElement& element : header.elements) {
        for (uint64_t row = 0; row < element.count; ++row) {
            for (const PlyProperty& property : element.properties) {
                if (property.is_list) {
                    body.skip_values(property.type,
                                     body.read_list_size(property.list_size_type, property.type));
                    continue;
                }
                const double value = body.read_value(property.type) * property.scale + property.shift;
                const auto as_float = static_cast<float>(value);
                switch (property.role) {
                    case Role::Ignore: break;
                    case Role::X: points[row].x = as_float; break;
                    case Role::Y: points[row].y = as_float; break;
                    case Role::Z: points[row].z = as_float; break;
                    case Role::Red: color[3 * row] = as_float; break;
                    case Role::Green: color[3 * row + 1] = as_float; break;
                    case Role::Blue: color[3 * row + 2] = as_float; break;
                    case Role::Radius: radius[row] = as_float; break;
                    case Role::StrandSize:
                        if (value < 2.0)
                            throw Error("strand " + std::to_string(row) + " has " +
                                        std::to_string(static_cast<int64_t>(value)) +
                                        " point(s); every strand needs at least 2");
                        if (value > static_cast<double>(vertex_count - strand_points))
                            throw Error("strands need more points than the " +
                                        std::to_string(vertex_count) + " vertices");
                        strand_sizes[row] = static_cast<int64_t>(value);
                        strand_points += strand_sizes[row];
                        break;
                }
            }
        }
    }
    body.expect_end();
    if (strand_points != vertex_count)
        throw Error("strands have " + std::to_string(strand_points) + " points but there are " +
                    std::to_string(vertex_count) + " vertices");

    if (!vertex_roles.has_radius) radius.assign(vertex_count, resolve_default_radius(options, points));
    StrandSet strands = strands_from_counts(std::move(points), strand_sizes, std::move(radius));
    if (vertex_roles.has_color) {
        require_finite(color, "color");
        strands.set_attribute("color", AttributeDomain::Point, 3, std::move(color));
    }
    return strands;
}

}  // namespace hairlod::io
