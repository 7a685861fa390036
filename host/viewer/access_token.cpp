#include "viewer/access_token.h"

#include <sys/random.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace ray {

std::string newAccessToken() {
    std::array<unsigned char, 16> bytes{};
    size_t filled = 0;
    while (filled < bytes.size()) {
        ssize_t got = getrandom(bytes.data() + filled, bytes.size() - filled, 0);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw std::runtime_error(std::string("cannot make an access token: ") + std::strerror(errno));
        filled += size_t(got);
    }
    static const char* hex = "0123456789abcdef";
    std::string token;
    for (unsigned char b : bytes) {
        token += hex[b >> 4];
        token += hex[b & 15];
    }
    return token;
}

std::string accessCookieName(int port) { return "ray_view_token_" + std::to_string(port); }

namespace {

std::string trimmed(const std::string& text) {
    const size_t first = text.find_first_not_of(" \t");
    if (first == std::string::npos) return "";
    return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

}  // namespace

std::string cookieValue(const std::string& header, const std::string& name) {
    size_t start = 0;
    while (start <= header.size()) {
        size_t end = header.find(';', start);
        if (end == std::string::npos) end = header.size();
        const std::string pair = trimmed(header.substr(start, end - start));
        const size_t equals = pair.find('=');
        if (equals != std::string::npos && pair.substr(0, equals) == name) return pair.substr(equals + 1);
        start = end + 1;
    }
    return "";
}

std::string authorizationToken(const std::string& header) {
    const std::string scheme = "token ";
    if (header.size() > scheme.size() && strncasecmp(header.c_str(), scheme.c_str(), scheme.size()) == 0)
        return trimmed(header.substr(scheme.size()));
    return "";
}

bool tokensMatch(const std::string& presented, const std::string& expected) {
    if (presented.size() != expected.size() || expected.empty()) return false;
    unsigned char difference = 0;
    for (size_t i = 0; i < expected.size(); ++i) difference |= uint8_t(presented[i] ^ expected[i]);
    return difference == 0;
}

}  // namespace ray
