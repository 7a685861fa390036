#include "scene/obj_reader.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <future>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include <tiny_obj_loader.h>

#include "scene/scene.h"

namespace ray {

namespace {

// ---------------------------------------------------------------------------------------
// Lines and tokens, as tinyobjloader reads them. A line ends at '\n', '\r' or "\r\n"; its
// content ends there or at a NUL byte (tinyobjloader read each line as a C string). Every
// helper stops at the content's end, never reading into the next line.

bool isBlank(char c) { return c == ' ' || c == '\t'; }
bool isDigit(char c) { return static_cast<unsigned>(c - '0') < 10u; }

// strspn(p, " \t")
const char* skipBlanks(const char* p, const char* end) {
    while (p < end && isBlank(*p)) ++p;
    return p;
}

// strcspn(p, " \t\r"): no '\r' is inside a line.
const char* tokenEnd(const char* p, const char* end) {
    while (p < end && !isBlank(*p)) ++p;
    return p;
}

// strcspn(p, "/ \t\r")
const char* indexEnd(const char* p, const char* end) {
    while (p < end && *p != '/' && !isBlank(*p)) ++p;
    return p;
}

// atoi(p) as glibc computes it, (int) strtol(p, nullptr, 10): leading white space, a sign,
// digits; a value beyond long saturates, and the cast keeps the low 32 bits.
int cAtoi(const char* p, const char* end) {
    while (p < end && (isBlank(*p) || *p == '\v' || *p == '\f')) ++p;
    bool negative = false;
    if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
    constexpr uint64_t kBeyond = (uint64_t(1) << 63) + 1;  // saturates the magnitude
    uint64_t magnitude = 0;
    for (; p < end && isDigit(*p); ++p) {  // checked before the multiplication, which could wrap
        const uint64_t digit = uint64_t(*p - '0');
        magnitude = magnitude > (kBeyond - digit) / 10 ? kBeyond : magnitude * 10 + digit;
    }
    int64_t value;
    if (negative) value = magnitude >= (uint64_t(1) << 63) ? INT64_MIN : -int64_t(magnitude);
    else value = magnitude > uint64_t(INT64_MAX) ? INT64_MAX : int64_t(magnitude);
    return static_cast<int32_t>(static_cast<uint32_t>(static_cast<uint64_t>(value)));
}

// tinyobjloader's tryParseDouble, step for step (so that every coordinate rounds as it did):
// [sign] digits [. digits] [(e|E) [sign] digits], read greedily from s, never past sEnd.
bool tryParseDouble(const char* s, const char* sEnd, double* result) {
    if (s >= sEnd) return false;
    double mantissa = 0.0;
    int exponent = 0;
    char sign = '+', expSign = '+';
    const char* curr = s;
    int read = 0;
    bool endNotReached = false;
    bool leadingDecimalDots = false;

    if (*curr == '+' || *curr == '-') {
        sign = *curr;
        curr++;
        if (curr != sEnd && *curr == '.') leadingDecimalDots = true;
    } else if (isDigit(*curr)) {
    } else if (*curr == '.') {
        leadingDecimalDots = true;
    } else {
        return false;
    }

    endNotReached = curr != sEnd;
    if (!leadingDecimalDots) {
        while (endNotReached && isDigit(*curr)) {
            mantissa *= 10;
            mantissa += static_cast<int>(*curr - 0x30);
            curr++;
            read++;
            endNotReached = curr != sEnd;
        }
        if (read == 0) return false;
    }
    if (!endNotReached) goto assemble;

    if (*curr == '.') {
        curr++;
        read = 1;
        endNotReached = curr != sEnd;
        while (endNotReached && isDigit(*curr)) {
            static const double powLut[] = {1.0, 0.1, 0.01, 0.001, 0.0001, 0.00001, 0.000001, 0.0000001};
            const int lutEntries = sizeof powLut / sizeof powLut[0];
            mantissa += static_cast<int>(*curr - 0x30) * (read < lutEntries ? powLut[read] : std::pow(10.0, -read));
            read++;
            curr++;
            endNotReached = curr != sEnd;
        }
    } else if (*curr == 'e' || *curr == 'E') {
    } else {
        goto assemble;
    }
    if (!endNotReached) goto assemble;

    if (*curr == 'e' || *curr == 'E') {
        curr++;
        endNotReached = curr != sEnd;
        if (endNotReached && (*curr == '+' || *curr == '-')) {
            expSign = *curr;
            curr++;
        } else if (endNotReached && isDigit(*curr)) {  // sEnd is never at a digit
        } else {
            return false;
        }
        read = 0;
        endNotReached = curr != sEnd;
        while (endNotReached && isDigit(*curr)) {
            if (exponent > (2147483647 / 10)) return false;
            exponent *= 10;
            exponent += static_cast<int>(*curr - 0x30);
            curr++;
            read++;
            endNotReached = curr != sEnd;
        }
        exponent *= (expSign == '+' ? 1 : -1);
        if (read == 0) return false;
    }

assemble:
    *result = (sign == '+' ? 1 : -1) *
              (exponent ? std::ldexp(mantissa * std::pow(5.0, exponent), exponent) : mantissa);
    return true;
}

// tinyobjloader's parseReal: the next token as a float, `fallback` when it is not a number.
float parseReal(const char*& p, const char* end, double fallback = 0.0) {
    p = skipBlanks(p, end);
    const char* stop = tokenEnd(p, end);
    double value = fallback;
    tryParseDouble(p, stop, &value);
    p = stop;
    return static_cast<float>(value);
}

// An index as the line gives it, made zero-based: positive counts from 1, negative back
// from the count read so far (`relative` then records that the chunk's base must be
// added); 0 is an error.
bool fixIndex(int index, int countSoFar, int32_t* out, bool* relative) {
    if (index > 0) {
        *out = index - 1;
        return true;
    }
    if (index == 0) return false;
    *out = countSoFar + index;
    *relative = true;
    return true;
}

// One corner of a face as read: indices into the whole file's arrays once `relative`
// entries (bits 1 position, 2 texture coordinate, 4 normal) get their chunk's base added;
// -1 where the corner names none.
struct RawCorner {
    int32_t position = -1, texCoord = -1, normal = -1;
    uint8_t relative = 0;
};

struct Counts {
    int positions = 0, normals = 0, texCoords = 0;
};

// tinyobjloader's parseTriple: i, i/j, i//k or i/j/k. False for an index of 0 or a missing
// one (atoi's 0).
bool parseCorner(const char*& p, const char* end, const Counts& counts, RawCorner* corner) {
    RawCorner c;
    // One index, fixed as tinyobjloader fixes it, its relative flag kept; p past its digits.
    const auto index = [&](int countSoFar, int32_t* out, uint8_t relativeFlag) {
        bool relative = false;
        if (!fixIndex(cAtoi(p, end), countSoFar, out, &relative)) return false;
        if (relative) c.relative |= relativeFlag;
        p = indexEnd(p, end);
        return true;
    };
    const auto slash = [&] { return p < end && *p == '/' ? (++p, true) : false; };
    if (!index(counts.positions, &c.position, 1)) return false;
    if (slash()) {
        if (slash()) {  // i//k
            if (!index(counts.normals, &c.normal, 4)) return false;
        } else {  // i/j or i/j/k
            if (!index(counts.texCoords, &c.texCoord, 2)) return false;
            if (slash() && !index(counts.normals, &c.normal, 4)) return false;
        }
    }
    *corner = c;
    return true;
}

// ---------------------------------------------------------------------------------------
// A chunk of lines, parsed on its own

// A line that changes how later polygons are triangulated or that reads a library: g and o
// close the group (its polygons are triangulated over the vertices read so far), usemtl
// closes it when the material changes, mtllib reads libraries.
struct GroupLine {
    enum class Kind { Close, UseMaterial, MaterialLibrary } kind;
    int positionsBefore;  // of this chunk, read before the line
    std::string text;     // usemtl: the name; mtllib: the rest of the line
};

// A face that is not a triangle: fewer corners (dropped) or more (triangulated later).
struct Polygon {
    size_t firstCorner;
    uint32_t corners;
    size_t groupLinesBefore;  // this chunk's GroupLines before the face
    int visiblePositions = 0;  // the whole file's count when its group closes (set on joining)
    std::vector<std::array<RawCorner, 3>> triangles;  // made on joining
};

struct Chunk {
    const char* begin;
    const char* end;
    std::vector<float> positions, normals, texCoords;  // 3, 3 and 2 a line
    std::vector<RawCorner> corners;                    // every face's, in order
    std::vector<Polygon> polygons;                     // the faces with other than 3 corners
    std::vector<GroupLine> groupLines;
    size_t lines = 0;  // read (to the first error, included)
    // The first line that cannot be read: tinyobjloader's text up to its number, and the
    // line's number within the chunk.
    std::optional<std::string> error;
    size_t errorLine = 0;
    // Joining:
    Counts base;
    size_t firstLine = 0;  // lines before the chunk
    size_t firstTriangle = 0;
    size_t triangles = 0;
};

size_t countPositions(const Chunk& chunk) { return chunk.positions.size() / 3; }

Counts countsSoFar(const Chunk& chunk) {
    return {int(chunk.positions.size() / 3), int(chunk.normals.size() / 3), int(chunk.texCoords.size() / 2)};
}

// Parses one line's content [p, end) (its leading blanks included); false at an error,
// with chunk.error set.
class ChunkParser {
public:
    explicit ChunkParser(Chunk& chunk) : chunk_(chunk) {}

    void parse() {
        const char* p = chunk_.begin;
        const char* const stop = chunk_.end;
        while (p < stop) {
            ++chunk_.lines;
            const char* lineEnd = p;
            const char* contentEnd = nullptr;
            while (lineEnd < stop && *lineEnd != '\n' && *lineEnd != '\r') {
                if (*lineEnd == '\0' && !contentEnd) contentEnd = lineEnd;
                ++lineEnd;
            }
            if (!contentEnd) contentEnd = lineEnd;
            if (!parseLine(p, contentEnd)) return;
            p = lineEnd;
            if (p < stop) p += (*p == '\r' && p + 1 < stop && p[1] == '\n') ? 2 : 1;
        }
    }

private:
    // `text`: tinyobjloader's message, up to the line's number.
    bool fail(const std::string& text) {
        chunk_.error = text;
        chunk_.errorLine = chunk_.lines;
        return false;
    }

    bool parseLine(const char* p, const char* end) {
        p = skipBlanks(p, end);
        if (p == end || *p == '#') return true;
        const char c0 = *p, c1 = p + 1 < end ? p[1] : '\0', c2 = p + 2 < end ? p[2] : '\0';
        if (c0 == 'v' && isBlank(c1)) return readFloats(p + 2, end, 3, chunk_.positions);
        if (c0 == 'v' && c1 == 'n' && isBlank(c2)) return readFloats(p + 3, end, 3, chunk_.normals);
        if (c0 == 'v' && c1 == 't' && isBlank(c2)) return readFloats(p + 3, end, 2, chunk_.texCoords);
        if (c0 == 'v' && c1 == 'w' && isBlank(c2)) return checkSkinWeights(p + 3, end);
        if (c0 == 'l' && isBlank(c1)) return checkIndexList(p + 2, end, 'l');
        if (c0 == 'p' && isBlank(c1)) return checkIndexList(p + 2, end, 'p');
        if (c0 == 'f' && isBlank(c1)) return readFace(skipBlanks(p + 2, end), end);
        if (end - p >= 6 && std::memcmp(p, "usemtl", 6) == 0) {
            const char* name = skipBlanks(p + 6, end);
            addGroupLine(GroupLine::Kind::UseMaterial, std::string(name, tokenEnd(name, end)));
            return true;
        }
        if (end - p >= 7 && std::memcmp(p, "mtllib", 6) == 0 && isBlank(p[6])) {
            addGroupLine(GroupLine::Kind::MaterialLibrary, std::string(p + 7, end));
            return true;
        }
        if ((c0 == 'g' || c0 == 'o') && isBlank(c1)) addGroupLine(GroupLine::Kind::Close, {});
        return true;  // t, s and anything unknown: nothing a mesh keeps
    }

    // v: x y z (a vertex colour after them is not kept); vn: x y z; vt: u v. A missing or
    // unreadable number is 0.
    bool readFloats(const char* p, const char* end, int count, std::vector<float>& out) {
        for (int i = 0; i < count; ++i) out.push_back(parseReal(p, end));
        return true;
    }

    // vw (a tinyobjloader extension, skin weights): not kept, but a negative joint is its
    // error.
    bool checkSkinWeights(const char* p, const char* end) {
        p = tokenEnd(skipBlanks(p, end), end);  // the vertex
        while (p < end) {
            float joint = parseReal(p, end, -1.0);
            (void)parseReal(p, end);  // the weight
            if (joint < 0.0f)
                return fail("Failed parse `vw' line. joint_id is negative. line ");
            p = skipBlanks(p, end);
        }
        return true;
    }

    // l and p: not kept, but an index of 0 is an error.
    bool checkIndexList(const char* p, const char* end, char kind) {
        const Counts counts = countsSoFar(chunk_);
        while (p < end) {
            RawCorner ignored;
            if (!parseCorner(p, end, counts, &ignored))
                return fail(std::string("Failed parse `") + kind + "' line(e.g. zero value for vertex index. line ");
            p = skipBlanks(p, end);
        }
        return true;
    }

    bool readFace(const char* p, const char* end) {
        const Counts counts = countsSoFar(chunk_);
        const size_t first = chunk_.corners.size();
        while (p < end) {
            RawCorner corner;
            if (!parseCorner(p, end, counts, &corner)) {
                chunk_.corners.resize(first);
                return fail("Failed parse `f' line(e.g. zero value for face index. line ");
            }
            chunk_.corners.push_back(corner);
            p = skipBlanks(p, end);
        }
        const size_t corners = chunk_.corners.size() - first;
        if (corners != 3) chunk_.polygons.push_back({first, uint32_t(corners), chunk_.groupLines.size(), 0, {}});
        return true;
    }

    void addGroupLine(GroupLine::Kind kind, std::string text) {
        chunk_.groupLines.push_back({kind, int(countPositions(chunk_)), std::move(text)});
    }

    Chunk& chunk_;
};

// ---------------------------------------------------------------------------------------
// Cutting and joining

constexpr size_t kMinChunkBytes = size_t(1) << 20;  // below this a thread costs more than it saves

// Pieces (a thread each) a core: more threads than cores is deliberate, as in the BVH's
// build; the operating system hands the cores to the pieces left, so one thread
// descheduled on a shared machine holds up a small piece, not half of the file (37.7 MB
// read 35% faster with four a core than with one, alternating, on 2 busy cores).
constexpr size_t kChunksPerCore = 4;

std::vector<Chunk> cutIntoChunks(std::string_view text, int requested) {
    size_t count = requested > 0 ? size_t(requested)
                                 : std::clamp<size_t>(text.size() / kMinChunkBytes, 1,
                                                      kChunksPerCore * std::max(1u, std::thread::hardware_concurrency()));
    std::vector<Chunk> chunks;
    const char* const begin = text.data();
    const char* const end = begin + text.size();
    const char* start = begin;
    for (size_t i = 1; i <= count && start < end; ++i) {
        const char* stop = end;
        if (i < count) {
            // Just after a '\n', which always ends a line (alone or as "\r\n"), so the cut
            // falls where tinyobjloader started a line.
            const char* target = std::max(start, begin + text.size() / count * i);
            const void* newline = std::memchr(target, '\n', size_t(end - target));
            stop = newline ? static_cast<const char*>(newline) + 1 : end;
        }
        Chunk chunk;
        chunk.begin = start;
        chunk.end = stop;
        chunks.push_back(std::move(chunk));
        start = stop;
    }
    return chunks;
}

template <class Body>
void forEachChunk(std::vector<Chunk>& chunks, const Body& body) {
    std::vector<std::future<void>> others;
    for (size_t i = 1; i < chunks.size(); ++i)
        others.push_back(std::async(std::launch::async, [&, i] { body(chunks[i]); }));
    if (!chunks.empty()) body(chunks[0]);
    for (std::future<void>& f : others) f.get();
}

// tinyobjloader's SplitString(s, ' ', '\\'): a backslash escapes the next character; empty
// pieces are dropped, except the last.
std::vector<std::string> splitLibraryNames(const std::string& s) {
    std::vector<std::string> names;
    std::string name;
    bool escaping = false;
    for (char ch : s) {
        if (escaping) {
            escaping = false;
        } else if (ch == '\\') {
            escaping = true;
            continue;
        } else if (ch == ' ') {
            if (!name.empty()) names.push_back(name);
            name.clear();
            continue;
        }
        name += ch;
    }
    names.push_back(name);
    return names;
}

// The state tinyobjloader kept over the lines that decide groups: the libraries read, the
// material names they gave, the current material.
class GroupState {
public:
    explicit GroupState(tinyobj::MaterialReader* reader) : reader_(reader) {}

    // Whether the line closes the current group.
    bool apply(const GroupLine& line, std::string& errors) {
        switch (line.kind) {
            case GroupLine::Kind::Close: return true;
            case GroupLine::Kind::UseMaterial: {
                auto found = materialMap_.find(line.text);
                int id = found == materialMap_.end() ? -1 : found->second;
                bool changed = id != material_;
                material_ = id;
                return changed;
            }
            case GroupLine::Kind::MaterialLibrary: readLibraries(line.text, errors); return false;
        }
        return false;
    }

private:
    void readLibraries(const std::string& rest, std::string& errors) {
        if (!reader_) return;
        for (const std::string& name : splitLibraryNames(rest)) {
            if (filenames_.count(name) > 0) continue;
            std::string warnings, libraryErrors;
            bool ok = (*reader_)(name, &materials_, &materialMap_, &warnings, &libraryErrors);
            errors += libraryErrors;
            if (ok) {
                filenames_.insert(name);
                break;
            }
        }
    }

    tinyobj::MaterialReader* reader_;
    std::vector<tinyobj::material_t> materials_;
    std::map<std::string, int> materialMap_;
    std::set<std::string> filenames_;
    int material_ = -1;
};

// Walks the group lines in file order (to the first error): reads the libraries and gives
// each polygon the count of vertices read when its group closes. Returns the chunks that
// count (those after an error's are dropped) and tinyobjloader's error text.
std::string walkGroupLines(std::vector<Chunk>& chunks, tinyobj::MaterialReader* reader) {
    GroupState state(reader);
    std::string errors;
    std::vector<Polygon*> open;  // polygons of the current group
    for (Chunk& chunk : chunks) {
        size_t nextPolygon = 0;
        for (size_t g = 0; g <= chunk.groupLines.size(); ++g) {
            while (nextPolygon < chunk.polygons.size() && chunk.polygons[nextPolygon].groupLinesBefore <= g)
                open.push_back(&chunk.polygons[nextPolygon++]);
            if (g == chunk.groupLines.size()) break;
            const GroupLine& line = chunk.groupLines[g];
            if (state.apply(line, errors)) {
                for (Polygon* polygon : open) polygon->visiblePositions = chunk.base.positions + line.positionsBefore;
                open.clear();
            }
        }
    }
    const int total = chunks.empty() ? 0 : chunks.back().base.positions + int(countPositions(chunks.back()));
    for (Polygon* polygon : open) polygon->visiblePositions = total;
    return errors;
}

RawCorner resolve(RawCorner c, const Counts& base) {
    if (c.relative & 1) c.position += base.positions;
    if (c.relative & 2) c.texCoord += base.texCoords;
    if (c.relative & 4) c.normal += base.normals;
    c.relative = 0;
    return c;
}

// ---------------------------------------------------------------------------------------
// Triangulation of polygons, as tinyobjloader's exportGroupsToShape (float arithmetic on
// the vertices read when the group closed).

// Vertex coordinates as tinyobjloader held them: float, only the first `visible` vertices.
struct VisiblePositions {
    const std::vector<Vec3>& all;
    int visible;

    bool has(int32_t index) const { return index >= 0 && index < visible; }
    float at(int32_t index, size_t axis) const { return float(all[size_t(index)][int(axis)]); }
};

template <class T>
int pnpoly(int nvert, T* vertx, T* verty, T testx, T testy) {
    int i, j, c = 0;
    for (i = 0, j = nvert - 1; i < nvert; j = i++) {
        if (((verty[i] > testy) != (verty[j] > testy)) &&
            (testx < (vertx[j] - vertx[i]) * (testy - verty[i]) / (verty[j] - verty[i]) + vertx[i]))
            c = !c;
    }
    return c;
}

void triangulateQuad(const RawCorner* q, const VisiblePositions& v, std::vector<std::array<RawCorner, 3>>& out) {
    for (int k = 0; k < 4; ++k)
        if (!v.has(q[k].position)) return;  // tinyobjloader skips it ("invalid vertex index")
    float e02x = v.at(q[2].position, 0) - v.at(q[0].position, 0);
    float e02y = v.at(q[2].position, 1) - v.at(q[0].position, 1);
    float e02z = v.at(q[2].position, 2) - v.at(q[0].position, 2);
    float e13x = v.at(q[3].position, 0) - v.at(q[1].position, 0);
    float e13y = v.at(q[3].position, 1) - v.at(q[1].position, 1);
    float e13z = v.at(q[3].position, 2) - v.at(q[1].position, 2);
    float sqr02 = e02x * e02x + e02y * e02y + e02z * e02z;
    float sqr13 = e13x * e13x + e13y * e13y + e13z * e13z;
    if (sqr02 < sqr13) {
        out.push_back({q[0], q[1], q[2]});
        out.push_back({q[0], q[2], q[3]});
    } else {
        out.push_back({q[0], q[1], q[3]});
        out.push_back({q[1], q[2], q[3]});
    }
}

// tinyobjloader's built-in ear clipping, step for step.
void triangulateLarger(const RawCorner* face, size_t n, const VisiblePositions& v,
                       std::vector<std::array<RawCorner, 3>>& out) {
    size_t axes[2] = {1, 2};
    for (size_t k = 0; k < n; ++k) {
        const RawCorner &i0 = face[(k + 0) % n], &i1 = face[(k + 1) % n], &i2 = face[(k + 2) % n];
        if (!v.has(i0.position) || !v.has(i1.position) || !v.has(i2.position)) continue;
        float v0x = v.at(i0.position, 0), v0y = v.at(i0.position, 1), v0z = v.at(i0.position, 2);
        float v1x = v.at(i1.position, 0), v1y = v.at(i1.position, 1), v1z = v.at(i1.position, 2);
        float v2x = v.at(i2.position, 0), v2y = v.at(i2.position, 1), v2z = v.at(i2.position, 2);
        float e0x = v1x - v0x, e0y = v1y - v0y, e0z = v1z - v0z;
        float e1x = v2x - v1x, e1y = v2y - v1y, e1z = v2z - v1z;
        float cx = std::fabs(e0y * e1z - e0z * e1y);
        float cy = std::fabs(e0z * e1x - e0x * e1z);
        float cz = std::fabs(e0x * e1y - e0y * e1x);
        const float epsilon = std::numeric_limits<float>::epsilon();
        if (cx > epsilon || cy > epsilon || cz > epsilon) {
            if (!(cx > cy && cx > cz)) {
                axes[0] = 0;
                if (cz > cx && cz > cy) axes[1] = 1;
            }
            break;
        }
    }

    std::vector<RawCorner> remaining(face, face + n);
    size_t guessVert = 0;
    RawCorner ind[3];
    float vx[3], vy[3];
    size_t remainingIterations = n;
    size_t previousRemainingVertices = remaining.size();
    while (remaining.size() > 3 && remainingIterations > 0) {
        size_t npolys = remaining.size();
        if (guessVert >= npolys) guessVert -= npolys;
        if (previousRemainingVertices != npolys) {
            previousRemainingVertices = npolys;
            remainingIterations = npolys;
        } else {
            remainingIterations--;
        }
        for (size_t k = 0; k < 3; k++) {
            ind[k] = remaining[(guessVert + k) % npolys];
            if (!v.has(ind[k].position)) {
                vx[k] = 0.0f;
                vy[k] = 0.0f;
            } else {
                vx[k] = v.at(ind[k].position, axes[0]);
                vy[k] = v.at(ind[k].position, axes[1]);
            }
        }
        float e0x = vx[1] - vx[0], e0y = vy[1] - vy[0];
        float e1x = vx[2] - vx[1], e1y = vy[2] - vy[1];
        float cross = e0x * e1y - e0y * e1x;
        float area = (vx[0] * vy[1] - vy[0] * vx[1]) * 0.5f;
        if (cross * area < 0.0f) {
            guessVert += 1;
            continue;
        }
        bool overlap = false;
        for (size_t otherVert = 3; otherVert < npolys; ++otherVert) {
            size_t idx = (guessVert + otherVert) % npolys;
            if (idx >= remaining.size()) continue;
            int32_t ovi = remaining[idx].position;
            if (!v.has(ovi)) continue;
            float tx = v.at(ovi, axes[0]), ty = v.at(ovi, axes[1]);
            if (pnpoly(3, vx, vy, tx, ty)) {
                overlap = true;
                break;
            }
        }
        if (overlap) {
            guessVert += 1;
            continue;
        }
        out.push_back({ind[0], ind[1], ind[2]});
        size_t removed = (guessVert + 1) % npolys;
        while (removed + 1 < npolys) {
            remaining[removed] = remaining[removed + 1];
            removed += 1;
        }
        remaining.pop_back();
    }
    if (remaining.size() == 3) out.push_back({remaining[0], remaining[1], remaining[2]});
}

void triangulate(Chunk& chunk, const std::vector<Vec3>& positions) {
    for (Polygon& polygon : chunk.polygons) {
        if (polygon.corners < 3) continue;  // tinyobjloader drops it ("degenerated face")
        std::vector<RawCorner> face(polygon.corners);
        for (uint32_t k = 0; k < polygon.corners; ++k)
            face[k] = resolve(chunk.corners[polygon.firstCorner + k], chunk.base);
        const VisiblePositions v{positions, polygon.visiblePositions};
        if (polygon.corners == 4) triangulateQuad(face.data(), v, polygon.triangles);
        else triangulateLarger(face.data(), face.size(), v, polygon.triangles);
    }
}

// ---------------------------------------------------------------------------------------
// The mesh

// A triangle's corner as the mesh stores it: a position that does not exist makes the face
// an error; a normal or texture coordinate that does not exist is none.
struct CornerCheck {
    size_t positions, normals, texCoords;

    bool store(const RawCorner& c, MeshCorner* out) const {
        out->position = c.position;
        out->normal = c.normal >= 0 && size_t(c.normal) < normals ? c.normal : -1;
        out->texCoord = c.texCoord >= 0 && size_t(c.texCoord) < texCoords ? c.texCoord : -1;
        return c.position >= 0 && size_t(c.position) < positions;
    }
};

// The chunk's triangles in file order; false if one names a missing vertex.
bool storeTriangles(const Chunk& chunk, const CornerCheck& check, TriangleMesh& mesh, Vec3* lo, Vec3* hi) {
    auto* out = mesh.triangles.data() + chunk.firstTriangle;  // not [i]: it may be the end
    bool valid = true;
    auto put = [&](const RawCorner& a, const RawCorner& b, const RawCorner& c, bool resolved) {
        std::array<MeshCorner, 3>& t = *out++;
        const RawCorner corners[3] = {resolved ? a : resolve(a, chunk.base), resolved ? b : resolve(b, chunk.base),
                                      resolved ? c : resolve(c, chunk.base)};
        for (int k = 0; k < 3; ++k) {
            if (!check.store(corners[k], &t[size_t(k)])) {
                valid = false;
                continue;
            }
            const Vec3& p = mesh.positions[size_t(t[size_t(k)].position)];
            *lo = componentMin(*lo, p);
            *hi = componentMax(*hi, p);
        }
    };
    size_t corner = 0;
    for (const Polygon& polygon : chunk.polygons) {
        for (; corner < polygon.firstCorner; corner += 3)
            put(chunk.corners[corner], chunk.corners[corner + 1], chunk.corners[corner + 2], false);
        for (const auto& t : polygon.triangles) put(t[0], t[1], t[2], true);
        corner = polygon.firstCorner + polygon.corners;
    }
    for (; corner < chunk.corners.size(); corner += 3)
        put(chunk.corners[corner], chunk.corners[corner + 1], chunk.corners[corner + 2], false);
    return valid;
}

void copyFloats3(const std::vector<float>& from, Vec3* to) {
    for (size_t i = 0; i + 2 < from.size(); i += 3) *to++ = {from[i], from[i + 1], from[i + 2]};
}

// The n of a line ending "line n", "line n." or "line n.)" (tinyobjloader's way of saying
// where), read by hand: no std::regex on text from outside (a long line overflowed its
// recursion).
std::optional<std::string> trailingLineNumber(const std::string& line) {
    size_t end = line.find_last_not_of(" \t\r");
    if (end == std::string::npos) return std::nullopt;
    if (line[end] == ')') --end;
    if (end != std::string::npos && line[end] == '.') --end;
    size_t begin = end + 1;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(line[begin - 1]))) --begin;
    if (begin > end || begin < 5 || line.compare(begin - 5, 5, "line ") != 0) return std::nullopt;
    return line.substr(begin, end + 1 - begin);
}

// tinyobjloader's error text: one or more lines such as "Failed parse `f' line(e.g. zero
// value for face index. line 2.)". Each becomes "file:line: error: ...", the form of the
// scene loader's messages, so no line of it is left without its file.
std::string describeObjErrors(const std::string& errors, const std::string& name) {
    std::istringstream lines(errors);
    std::string out, line;
    while (std::getline(lines, line)) {
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        const std::optional<std::string> number = trailingLineNumber(line);
        const std::string where = number ? name + ":" + *number : name;
        out += (out.empty() ? "" : "\n") + where + ": error: cannot read the OBJ file: " + line;
    }
    if (out.empty()) out = name + ": error: cannot read the OBJ file";
    return out + "\n(check that " + name + " is a Wavefront OBJ file)";
}

// tinyobjloader's text for the chunk's failing line, numbered in the file.
std::string errorText(const Chunk& chunk) {
    return *chunk.error + std::to_string(chunk.firstLine + chunk.errorLine) + ".)\n";
}

}  // namespace

TriangleMesh readObjMesh(std::string_view text, const std::string& nameForErrors, const ObjReadOptions& options) {
    std::vector<Chunk> chunks = cutIntoChunks(text, options.chunks);
    forEachChunk(chunks, [](Chunk& chunk) { ChunkParser(chunk).parse(); });

    // tinyobjloader stopped at the first line it could not read: the chunks after it count
    // for nothing.
    auto firstFailed = std::find_if(chunks.begin(), chunks.end(), [](const Chunk& c) { return c.error.has_value(); });
    const bool failed = firstFailed != chunks.end();
    if (failed) chunks.erase(firstFailed + 1, chunks.end());
    Counts base;
    size_t lines = 0;
    for (Chunk& chunk : chunks) {
        chunk.base = base;
        chunk.firstLine = lines;
        base.positions += int(chunk.positions.size() / 3);
        base.normals += int(chunk.normals.size() / 3);
        base.texCoords += int(chunk.texCoords.size() / 2);
        lines += chunk.lines;
    }
    std::string errors = walkGroupLines(chunks, options.materials);
    if (options.librariesRead) options.librariesRead();
    if (failed) {
        errors += errorText(chunks.back());
        throw InputError(describeObjErrors(errors, nameForErrors));
    }

    TriangleMesh mesh;
    mesh.positions.resize(size_t(base.positions));
    mesh.normals.resize(size_t(base.normals));
    mesh.texCoords.resize(size_t(base.texCoords));
    forEachChunk(chunks, [&](Chunk& chunk) {
        // data() + offset, not &[offset]: a chunk after the last normal starts at the end
        // (and an empty array's data() may be null), where [] would bind a reference to nothing.
        copyFloats3(chunk.positions, mesh.positions.data() + chunk.base.positions);
        copyFloats3(chunk.normals, mesh.normals.data() + chunk.base.normals);
        auto* uv = mesh.texCoords.data() + chunk.base.texCoords;
        for (size_t i = 0; i + 1 < chunk.texCoords.size(); i += 2) *uv++ = {chunk.texCoords[i], chunk.texCoords[i + 1]};
        std::vector<float>().swap(chunk.positions);
        std::vector<float>().swap(chunk.normals);
        std::vector<float>().swap(chunk.texCoords);
    });
    forEachChunk(chunks, [&](Chunk& chunk) { triangulate(chunk, mesh.positions); });

    size_t triangles = 0;
    for (Chunk& chunk : chunks) {
        size_t polygonCorners = 0, polygonTriangles = 0;
        for (const Polygon& polygon : chunk.polygons) {
            polygonCorners += polygon.corners;
            polygonTriangles += polygon.triangles.size();
        }
        chunk.firstTriangle = triangles;
        chunk.triangles = (chunk.corners.size() - polygonCorners) / 3 + polygonTriangles;
        triangles += chunk.triangles;
    }
    mesh.triangles.resize(triangles);
    const CornerCheck check{mesh.positions.size(), mesh.normals.size(), mesh.texCoords.size()};
    const Vec3 none{INFINITY, INFINITY, INFINITY};
    std::vector<Vec3> los(chunks.size(), none), his(chunks.size(), -none);
    std::vector<char> valid(chunks.size(), 1);
    forEachChunk(chunks, [&](Chunk& chunk) {
        const size_t i = size_t(&chunk - chunks.data());
        valid[i] = storeTriangles(chunk, check, mesh, &los[i], &his[i]);
    });
    if (std::find(valid.begin(), valid.end(), 0) != valid.end())
        throw InputError(nameForErrors + ": error: a face names a vertex that does not exist; check the file");
    if (mesh.triangles.empty())
        throw InputError(nameForErrors + ": error: the OBJ file holds no faces; a mesh needs at least one triangle");
    // In chunk order, as one pass over the triangles would take them (std::min keeps the
    // first of equal values: -0 and 0 stay as a single pass finds them).
    mesh.boundsLo = none;
    mesh.boundsHi = -none;
    for (size_t i = 0; i < chunks.size(); ++i) {
        mesh.boundsLo = componentMin(mesh.boundsLo, los[i]);
        mesh.boundsHi = componentMax(mesh.boundsHi, his[i]);
    }
    return mesh;
}

}  // namespace ray
