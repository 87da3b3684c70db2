#pragma once
// Procedural styling operations (hair-meshes-realtime.txt Sec. 3.4). Offsets are computed in the
// styling frame [u v w] of the strand vertex (d = M d^r) with amplitudes in object units, so a
// bundle that stretches keeps its curl radius. Phases run along w measured from the strand's root,
// so every offset vanishes at the root and the root stays on the scalp. Randomness in [0, 1]
// scales per-strand random variation; all randomness is a pure function of (seed, strand).
#include <cstdint>
#include <span>
#include <variant>
#include <vector>

#include <glm/vec3.hpp>

namespace hairlod {

// Helix around the strand: offset radius (cos phi - cos phi0) u + radius (sin phi - sin phi0) v with
// phi = phi0 + 2 pi frequency w. Randomness varies radius and frequency by up to +-50 % and
// spreads the start phase phi0 over up to a full turn.
struct Curl {
    float radius = 0.0f;     // object units
    float frequency = 0.0f;  // turns per unit of w
    float randomness = 0.0f;
};

// Planar wave along u: amplitude (sin(2 pi frequency w + phi0) - sin phi0) u; randomness spreads phi0.
struct Wave {
    float amplitude = 0.0f;  // object units
    float frequency = 0.0f;  // periods per unit of w
    float randomness = 0.0f;
};

// Rotates the strand about the bundle's centre curve, around w, by 2 pi rate w.
struct Twist {
    float rate = 0.0f;  // turns per unit of w
};

// Pulls the strand towards its bundle's centre curve by amount t^profile, t in [0, 1] the
// position along the strand (0 at the root).
struct Clump {
    float amount = 0.0f;   // fraction of the distance to the centre at the tip, in [0, 1]
    float profile = 1.0f;  // exponent > 0: larger keeps the clump nearer the tip
};

// Smooth per-strand value noise in the [u v w] frame: amplitude (n(frequency w) - n(0)).
struct Frizz {
    float amplitude = 0.0f;  // object units
    float frequency = 0.0f;  // noise cells per unit of w
};

// Shortens each strand to a random fraction in [1 - amount, 1] of its length (its curve
// parameter range), before the other operations; its place in the list does not matter.
struct Trim {
    float amount = 0.0f;  // in [0, 1]
};

using StylingOperation = std::variant<Curl, Wave, Twist, Clump, Frizz, Trim>;

// Throws Error naming the operation (by list index) and parameter that is out of range or not finite.
void validate_styling(std::span<const StylingOperation> operations);

// The vertices of one strand that the operations read and move, stored component by component
// (structure of arrays) so that each operation's loop over the vertices vectorises.
class StrandVertices {
public:
    enum Component {
        X, Y, Z,     // position
        UX, UY, UZ,  // styling frame u, v, w (Bhokare 2024 Eq. 1, 4): unit on the layers, interpolated between them
        VX, VY, VZ,
        WX, WY, WZ,
        CX, CY, CZ,   // the bundle's centre curve at the same curve parameter
        W_FROM_ROOT,  // styling w minus the root's w
        T,            // position along the strand in [0, 1]
        kComponentCount
    };

    // Each component array has room for kOverrun values past size(), so that a loop over blocks
    // of 4 vertices may write past the end into scratch instead of running a scalar remainder.
    static constexpr size_t kOverrun = 3;

    void resize(size_t count) {
        count_ = count;
        stride_ = (count + kOverrun + 3) / 4 * 4;  // multiples of 4 floats keep the arrays 16-byte apart
        values_.resize(stride_ * kComponentCount);
    }
    size_t size() const { return count_; }
    float* operator[](Component c) { return values_.data() + c * stride_; }
    const float* operator[](Component c) const { return values_.data() + c * stride_; }
    // Three consecutive components starting at X, UX, VX, WX or CX, as a vector.
    glm::vec3 vec3(Component first, size_t k) const {
        return {(*this)[first][k], (*this)[Component(first + 1)][k], (*this)[Component(first + 2)][k]};
    }
    void set_vec3(Component first, size_t k, const glm::vec3& value) {
        (*this)[first][k] = value.x;
        (*this)[Component(first + 1)][k] = value.y;
        (*this)[Component(first + 2)][k] = value.z;
    }

private:
    size_t count_ = 0, stride_ = 0;
    std::vector<float> values_;
};

// The StrandVertices components that a list of operations reads besides the position, so that a
// generator fills only those.
struct StylingInputs {
    bool u = false, v = false, w_axis = false, centre = false, w_from_root = false, t = false;
};
StylingInputs styling_inputs(std::span<const StylingOperation> operations);

// Per-strand constants of one operation, drawn once per strand.
struct OperationConstants {
    float amplitude = 0.0f;         // curl radius or wave amplitude after randomisation
    float angular_rate = 0.0f;      // 2 pi frequency after randomisation (curl, wave)
    float phase = 0.0f;             // phi0
    glm::vec3 at_root{0.0f};        // the operation's raw offset at the root, subtracted so roots stay
    uint64_t noise_key = 0;         // frizz
};

struct StrandStyling {
    std::vector<OperationConstants> operations;  // one per operation
    float length_fraction = 1.0f;                // product of the Trim operations

    // Scratch that apply_styling keeps between the strands styled with this object: frizz's
    // lattice values, and per clump operation t^profile at each vertex, reused while the profile
    // and the vertices' t stay the same (as for every strand of one generation).
    struct ClumpPull {
        float profile = 0.0f;
        std::vector<float> t, pull;
    };
    std::vector<float> noise_lattice;
    std::vector<ClumpPull> clump_pulls;
};

// Draws the per-strand constants into `strand`, reusing its storage (one call per generated strand).
void draw_strand_styling(std::span<const StylingOperation> operations, uint64_t seed, uint64_t strand_key,
                         StrandStyling& strand);

// Applies the operations in list order to the positions of vertices [first, size) of one strand,
// operation by operation (each loop is one operation's arithmetic over the strand). Generation
// passes first = 1: styling is not applied to the root (hair-meshes-realtime.txt Sec. 3.2).
void apply_styling(std::span<const StylingOperation> operations, StrandStyling& strand, StrandVertices& vertices,
                   size_t first);

}  // namespace hairlod
