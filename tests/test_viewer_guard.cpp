// Who ray view answers (viewer/request_guard.h) and how many connections without the token it
// keeps (viewer/connection_deadlines.h), the files a request may name
// (viewer/folder_files.h) and text from outside quoted in messages (core/message_text.h).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/message_text.h"
#include "viewer/connection_deadlines.h"
#include "viewer/folder_files.h"
#include "viewer/request_guard.h"
#include "viewer/view_request.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using ray::GuardPolicy;
using ray::RequestFacts;

const std::string kToken = "0123456789abcdef0123456789abcdef";
const GuardPolicy kPolicy{kToken, 8123, true};

// A request as the viewer's own page sends it (Chromium's headers).
RequestFacts fromThePage(const std::string& method, const std::string& path) {
    RequestFacts request;
    request.method = method;
    request.path = path;
    request.host = "127.0.0.1:8123";
    request.fetchSite = "same-origin";
    request.fetchMode = "cors";
    request.fetchDest = "empty";
    request.authorization = "token " + kToken;
    if (method == "POST") {
        request.origin = "http://127.0.0.1:8123";
        request.contentType = "application/json";
        request.hasBody = true;
    }
    return request;
}

int statusOf(const RequestFacts& request, const GuardPolicy& policy = kPolicy) {
    return ray::checkRequest(request, policy).status;
}

}  // namespace

TEST_CASE("The viewer answers its own page and scripts with the token", "[viewer][security]") {
    CHECK(statusOf(fromThePage("POST", "/edit")) == 0);
    CHECK(statusOf(fromThePage("GET", "/state")) == 0);
    RequestFacts script;  // a script: no browser headers, the token in Authorization
    script.method = "POST";
    script.path = "/save";
    script.host = "localhost:8123";
    script.authorization = "Token " + kToken;
    script.contentType = "application/json; charset=utf-8";
    script.hasBody = true;
    CHECK(statusOf(script) == 0);
    RequestFacts events = fromThePage("GET", "/events");  // EventSource takes no headers
    events.authorization.clear();
    events.queryToken = kToken;
    CHECK(statusOf(events) == 0);
}

TEST_CASE("The token's cookie opens the page and nothing else", "[viewer][security]") {
    RequestFacts page = fromThePage("GET", "/");
    page.authorization.clear();
    page.fetchMode = "navigate";
    page.fetchDest = "document";
    page.fetchSite = "none";
    page.cookie = "other=1; ray_view_token_8123=" + kToken;
    CHECK(statusOf(page) == 0);
    for (const char* path : {"/state", "/events", "/explain"}) {
        RequestFacts request = page;
        request.path = path;
        CHECK(statusOf(request) == 403);
    }
    RequestFacts edit = fromThePage("POST", "/edit");
    edit.authorization.clear();
    edit.cookie = page.cookie;
    CHECK(statusOf(edit) == 403);
    page.cookie = "ray_view_token_8124=" + kToken;  // another viewer's cookie
    CHECK(statusOf(page) == 403);
    RequestFacts first = page;  // the printed URL: the cookie is set, then a 303 to /
    first.cookie.clear();
    first.queryToken = kToken;
    const ray::GuardVerdict verdict = ray::checkRequest(first, kPolicy);
    CHECK(verdict.status == 0);
    CHECK_THAT(verdict.setCookie, Catch::StartsWith("ray_view_token_8123=" + kToken + ";") &&
                                      Catch::Contains("HttpOnly") && Catch::Contains("SameSite=Strict"));
}

TEST_CASE("Requests of another page are refused, even with the token", "[viewer][security]") {
    RequestFacts otherPort = fromThePage("POST", "/edit");
    otherPort.origin = "http://127.0.0.1:8000";
    otherPort.fetchSite = "same-site";
    CHECK(statusOf(otherPort) == 403);
    otherPort.origin.clear();  // no-cors requests may omit Origin; Fetch Metadata still tells
    CHECK(statusOf(otherPort) == 403);
    RequestFacts nullOrigin = fromThePage("POST", "/save");
    nullOrigin.origin = "null";
    CHECK(statusOf(nullOrigin) == 403);
    RequestFacts rebound = fromThePage("POST", "/edit");
    rebound.host = "evil.example:8123";
    rebound.origin = "http://evil.example:8123";
    CHECK(statusOf(rebound) == 403);
    CHECK(statusOf(rebound, GuardPolicy{kToken, 8123, false}) == 0);  // --bind 0.0.0.0: any name
    RequestFacts preflight = fromThePage("OPTIONS", "/edit");
    CHECK(statusOf(preflight) == 403);
    RequestFacts framed = fromThePage("GET", "/");
    framed.fetchDest = "iframe";
    CHECK(statusOf(framed) == 403);
    RequestFacts readByAnother = fromThePage("GET", "/");
    readByAnother.fetchSite = "cross-site";
    readByAnother.fetchMode = "no-cors";
    CHECK(statusOf(readByAnother) == 403);
    RequestFacts linkFollowed = readByAnother;
    linkFollowed.fetchMode = "navigate";
    linkFollowed.fetchDest = "document";
    CHECK(statusOf(linkFollowed) == 0);
    // --no-token: open, but still to the viewer's own page only.
    const GuardPolicy open{"", 8123, true};
    RequestFacts anonymous = fromThePage("POST", "/view");
    anonymous.authorization.clear();
    CHECK(statusOf(anonymous, open) == 0);
    anonymous.origin = "http://127.0.0.1:8000";
    CHECK(statusOf(anonymous, open) == 403);
}

TEST_CASE("With --frame-ancestors the page opens in a frame when the frame's URL holds the token",
          "[viewer][security]") {
    const GuardPolicy framable{kToken, 8123, true, "http://localhost:* http://127.0.0.1:*"};
    RequestFacts frame;  // a notebook's IFrame, at another port of the machine
    frame.method = "GET";
    frame.path = "/";
    frame.host = "127.0.0.1:8123";
    frame.fetchSite = "cross-site";
    frame.fetchMode = "navigate";
    frame.fetchDest = "iframe";
    frame.queryToken = kToken;
    const ray::GuardVerdict verdict = ray::checkRequest(frame, framable);
    CHECK(verdict.status == 0);
    CHECK(verdict.setCookie.empty());  // served at once: a cross-site frame sends no SameSite cookie back
    CHECK(statusOf(frame) == 403);     // without --frame-ancestors: never framed
    RequestFacts wrongToken = frame;
    wrongToken.queryToken = std::string(kToken.size(), '0');
    CHECK(statusOf(wrongToken, framable) == 403);
    RequestFacts cookieOnly = frame;  // the cookie alone does not open a frame
    cookieOnly.queryToken.clear();
    cookieOnly.cookie = "ray_view_token_8123=" + kToken;
    CHECK(statusOf(cookieOnly, framable) == 403);
    RequestFacts otherRoute = frame;  // only the page may be framed
    otherRoute.path = "/state";
    CHECK(statusOf(otherRoute, framable) == 403);
    RequestFacts post = fromThePage("POST", "/op");  // and the other page still cannot post
    post.origin = "http://127.0.0.1:8888";
    post.fetchSite = "same-site";
    CHECK(statusOf(post, framable) == 403);
}

TEST_CASE("A body must say it is JSON, which a form cannot", "[viewer][security]") {
    for (const char* type : {"text/plain", "application/x-www-form-urlencoded", "multipart/form-data; boundary=x", ""}) {
        RequestFacts form = fromThePage("POST", "/save");
        form.contentType = type;
        CHECK(statusOf(form) == 415);
    }
    RequestFacts bodiless = fromThePage("POST", "/undo");
    bodiless.contentType.clear();
    bodiless.hasBody = false;
    CHECK(statusOf(bodiless) == 0);
}

TEST_CASE("JSON is JSON whatever the case and spaces of its Content-Type", "[viewer][security]") {
    for (const char* type : {"application/json ; charset=utf-8", "Application/JSON;charset=UTF-8", " application/json",
                             "application/json\t; charset=utf-8"}) {
        RequestFacts request = fromThePage("POST", "/op");
        request.contentType = type;
        CHECK(statusOf(request) == 0);
    }
    for (const char* type : {"application/jsonx", "application/js on", "application/json-seq"}) {
        RequestFacts request = fromThePage("POST", "/op");
        request.contentType = type;
        CHECK(statusOf(request) == 415);
    }
}

TEST_CASE("The token counts in the query only for the page's URL and the event stream", "[viewer][security]") {
    for (const auto& [method, path] : {std::pair{"POST", "/op"}, {"POST", "/save"}, {"GET", "/state"}}) {
        RequestFacts request = fromThePage(method, path);
        request.authorization.clear();
        request.queryToken = kToken;
        const ray::GuardVerdict verdict = ray::checkRequest(request, kPolicy);
        CHECK(verdict.status == 403);
        CHECK_THAT(verdict.message, Catch::Contains("Authorization header"));
    }
    RequestFacts events = fromThePage("GET", "/events");
    events.authorization.clear();
    events.queryToken = kToken;
    CHECK(statusOf(events) == 0);
    RequestFacts page = fromThePage("GET", "/");
    page.authorization.clear();
    page.queryToken = kToken;
    CHECK(statusOf(page) == 0);
}

TEST_CASE("A body that is not UTF-8 is named as such", "[viewer][security]") {
    for (const std::string body : {"", "{\"name\": \"plain\"}", "{\"name\": \"é ✓ 𝄞\"}"})
        CHECK_FALSE(ray::bodyEncodingProblem(body));
    const std::pair<std::string, size_t> bad[] = {
        {"{\"name\": \"\xff\"}", 10},  // never in UTF-8
        {"ab\xc0\x80", 2},              // an overlong NUL
        {"\xed\xa0\x80", 0},           // a surrogate
        {"x\xe2\x82", 1},               // cut short
        {"\x80", 0},                     // a lone continuation byte
        {"\xf4\x90\x80\x80", 0},       // past U+10FFFF
    };
    for (const auto& [body, at] : bad) {
        const std::optional<std::string> problem = ray::bodyEncodingProblem(body);
        REQUIRE(problem);
        CHECK_THAT(*problem, Catch::Contains("not UTF-8") && Catch::Contains("byte " + std::to_string(at) + " "));
    }
}

TEST_CASE("Answers are valid UTF-8 whatever bytes a path holds", "[viewer]") {
    const nlohmann::json answer{{"file", "/tmp/caf\xe9/scene.xml"}, {"error", "cannot open '\xff\xfe'"}};
    std::string text;
    REQUIRE_NOTHROW(text = ray::jsonText(answer));
    CHECK_FALSE(ray::bodyEncodingProblem(text));
    CHECK(nlohmann::json::parse(text)["file"] == "/tmp/caf\xef\xbf\xbd/scene.xml");  // U+FFFD for the byte
}

TEST_CASE("Connections without the token beyond the bound close the oldest", "[viewer][security]") {
    ray::UnprovenConnections connections(2);
    int pairs[4][2];
    for (auto& pair : pairs) REQUIRE(socketpair(AF_UNIX, SOCK_STREAM, 0, pair) == 0);
    // The peer of a connection shut down reads its end at once; another's has nothing to read.
    auto shutDown = [](int peer) {
        char byte;
        return recv(peer, &byte, 1, MSG_DONTWAIT) == 0;
    };
    const uint64_t first = connections.enter(pairs[0][0]);
    const uint64_t second = connections.enter(pairs[1][0]);
    connections.prove(first);  // it showed the token: no longer counted
    connections.enter(pairs[2][0]);
    CHECK(connections.unproven() == 2);
    CHECK_FALSE(shutDown(pairs[0][1]));
    CHECK_FALSE(shutDown(pairs[1][1]));
    connections.enter(pairs[3][0]);  // a third without the token: the oldest of them goes
    CHECK(shutDown(pairs[1][1]));
    CHECK_FALSE(shutDown(pairs[0][1]));
    CHECK_FALSE(shutDown(pairs[2][1]));
    CHECK_FALSE(shutDown(pairs[3][1]));
    CHECK(connections.unproven() == 2);
    connections.leave(second);
    for (auto& pair : pairs) {
        close(pair[0]);
        close(pair[1]);
    }
}

TEST_CASE("Loopback addresses are known as such", "[viewer][security]") {
    for (const char* address : {"127.0.0.1", "127.1.2.3", "::1", "localhost", "LocalHost"})
        CHECK(ray::isLoopbackAddress(address));
    for (const char* address : {"0.0.0.0", "192.168.1.2", "::", "example.com"}) CHECK_FALSE(ray::isLoopbackAddress(address));
}

TEST_CASE("A request names files of the scene's folder only", "[viewer][security]") {
    const fs::path folder = ray::test::outputDir() / ("folder_files_" + std::to_string(::getpid()));
    const fs::path outside = ray::test::outputDir() / ("folder_files_outside_" + std::to_string(::getpid()));
    fs::remove_all(folder);
    fs::remove_all(outside);
    fs::create_directories(folder / "sub");
    fs::create_directories(outside);
    const fs::path real = fs::canonical(folder);
    CHECK(ray::fileInFolder(folder, "other.xml", "save as", {".xml"}) == real / "other.xml");
    CHECK(ray::fileInFolder(folder, "Other.XML", "save as", {".xml"}) == real / "Other.XML");
    CHECK(ray::fileInFolder(folder, (real / "abs.xml").string(), "save as", {".xml"}) == real / "abs.xml");
    const std::vector<std::string> leaving{"../x.xml", "../../x.xml", "sub/x.xml", "/tmp/x.xml", "..", ".", "", "x.txt",
                                   "x.xml/", std::string("a\0b.xml", 7), "a\nb.xml", "a\x7f.xml",
                                   (outside / "x.xml").string(), std::string(300, 'n') + ".xml",
                                   std::string(5000, 'n') + ".xml"};
    for (const std::string& name : leaving)
        CHECK_THROWS_AS(ray::fileInFolder(folder, name, "save as", {".xml"}), ray::BadFileName);
    try {
        ray::fileInFolder(folder, std::string(5000, 'n') + ".xml", "save as", {".xml"});
    } catch (const ray::BadFileName& e) {
        CHECK(std::string(e.what()).size() < 400);
    }
    try {
        ray::fileInFolder(folder, std::string("precious.txt\0.xml", 17), "save as", {".xml"});
    } catch (const ray::BadFileName& e) {
        CHECK_THAT(e.what(), Catch::Contains("precious.txt\\x00.xml") && Catch::Contains("control character"));
    }

    std::ofstream(folder / "exists.xml") << "mine";
    fs::create_symlink(outside / "target.xml", folder / "link.xml");
    CHECK_NOTHROW(ray::checkMayWrite(real / "new.xml", false, "save as"));
    CHECK_THROWS_AS(ray::checkMayWrite(real / "exists.xml", false, "save as"), ray::FileExists);
    CHECK_NOTHROW(ray::checkMayWrite(real / "exists.xml", true, "save as"));
    CHECK_THROWS_AS(ray::checkMayWrite(real / "link.xml", true, "save as"), ray::BadFileName);
    CHECK_THROWS_AS(ray::checkMayWrite(real / "sub", true, "save as"), ray::BadFileName);
    fs::remove_all(folder);
    fs::remove_all(outside);
}

TEST_CASE("Text from outside is quoted short and without control characters", "[security]") {
    CHECK(ray::quotedForMessage("scene.xml") == "scene.xml");
    CHECK(ray::quotedForMessage(std::string("a\0b\nc\td\x1b", 8)) == "a\\x00b\\nc\\td\\x1b");
    const std::string quoted = ray::quotedForMessage(std::string(100000, 'x') + "/name.xml");
    CHECK(quoted.size() <= ray::kMaxQuotedLength);
    CHECK_THAT(quoted, Catch::StartsWith("xxx") && Catch::EndsWith("/name.xml") && Catch::Contains("…"));
    std::string accents;  // two-byte characters: a cut never splits one
    for (int i = 0; i < 300; ++i) accents += "é";
    const std::string cut = ray::quotedForMessage(accents, 101);
    const size_t marker = cut.find("…");
    REQUIRE(marker != std::string::npos);
    CHECK(marker % 2 == 0);                                     // whole "é"s before it
    CHECK((cut.size() - marker - std::string("…").size()) % 2 == 0);  // and after it
    CHECK(static_cast<unsigned char>(cut[marker + 3]) == 0xC3);
}
