#include "viewer/viewer_routes.h"

#include <httplib.h>

#include <charconv>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/message_text.h"
#include "edit/edit_json.h"
#include "viewer/folder_files.h"
#include "viewer/request_guard.h"
#include "viewer/viewer_page.h"
#include "viewer/viewer_session.h"

namespace ray {

using nlohmann::json;

namespace {

void badRequest(httplib::Response& response, const std::string& why) {
    response.status = 400;
    response.set_content(json{{"error", why}}.dump(), "application/json");
}

// An edit refused: 400 with the sentence, the field and the node it is about; 409 for a
// name in use (docs/modeler-protocol.md).
void refused(httplib::Response& response, const EditError& error) {
    response.status = error.kind == EditError::Kind::Exists ? 409 : 400;
    response.set_content(edit::errorJson(error).dump(), "application/json");
}

// Answers with what `answer` returns, as JSON; a refused edit or a bad request (a missing or
// malformed parameter) as 400 with its sentence (refused, badRequest).
template <typename Answer>
void answerJson(httplib::Response& response, Answer&& answer) {
    try {
        response.set_content(answer().dump(), "application/json");
    } catch (const EditError& e) {
        refused(response, e);
    } catch (const std::exception& e) {
        badRequest(response, e.what());
    }
}

// A whole number from the query: "x must be a whole number" rather than std::stoi's "stoi".
int intParameter(const httplib::Request& request, const char* name) {
    const std::string text = request.get_param_value(name);
    int value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size())
        throw std::invalid_argument(std::string(name) + " must be a whole number" +
                                    (error == std::errc::result_out_of_range ? " in range" : "") + ", not '" +
                                    quotedForMessage(text, 40) + "'");
    return value;
}

// Whether a request comes with a body: the guard runs before cpp-httplib reads it, so its
// headers tell.
bool carriesBody(const httplib::Request& request) {
    const std::string length = request.get_header_value("Content-Length");
    return (!length.empty() && length != "0") || request.has_header("Transfer-Encoding");
}

// Headers every answer carries: it is never framed, read by another origin or sniffed.
void setProtectiveHeaders(httplib::Response& response) {
    response.set_header("X-Content-Type-Options", "nosniff");
    response.set_header("X-Frame-Options", "DENY");
    response.set_header("Cross-Origin-Resource-Policy", "same-origin");
    response.set_header("Referrer-Policy", "no-referrer");
}

// The check every request passes first (viewer/request_guard.h). A first visit to the page
// with the token in its query gets the cookie and is sent on to the bare URL.
httplib::Server::HandlerResponse guardRequest(const httplib::Request& request, httplib::Response& response,
                                              const GuardPolicy& policy) {
    using Result = httplib::Server::HandlerResponse;
    setProtectiveHeaders(response);
    const RequestFacts facts{request.method,
                             request.path,
                             request.get_header_value("Host"),
                             request.get_header_value("Origin"),
                             request.get_header_value("Sec-Fetch-Site"),
                             request.get_header_value("Sec-Fetch-Mode"),
                             request.get_header_value("Sec-Fetch-Dest"),
                             request.get_header_value("Content-Type"),
                             request.get_param_value("token"),
                             request.get_header_value("Authorization"),
                             request.get_header_value("Cookie"),
                             carriesBody(request)};
    const GuardVerdict verdict = checkRequest(facts, policy);
    if (verdict.status != 0) {
        response.status = verdict.status;
        response.set_content(json{{"error", verdict.message}}.dump(), "application/json");
        return Result::Handled;
    }
    if (!verdict.setCookie.empty()) {
        response.set_header("Set-Cookie", verdict.setCookie);
        response.set_redirect("/", 303);
        return Result::Handled;
    }
    return Result::Unhandled;
}

// An error answer that cpp-httplib made itself (a body over the limit, a request it could
// not read) says what went wrong, as every other answer does.
httplib::Server::HandlerResponse explainError(const httplib::Request&, httplib::Response& response) {
    if (!response.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
    std::string why = "the request was not understood (an HTTP request with a JSON body, and a Content-Length "
                      "for a POST)";
    if (response.status == 413)
        why = "the request's body is over the " + std::to_string(kMaxRequestBody / 1024) + " KiB limit";
    else if (response.status == 404)
        why = "there is no such route (the viewer serves /, /state, /settings, /fields, /outline, /node, /events, "
              "/view, /pick, /object, /explain, /op, /edit, /undo, /redo and /save)";
    response.set_content(json{{"error", why}}.dump(), "application/json");
    return httplib::Server::HandlerResponse::Handled;
}

// The page, with its token written in (request_guard.h says why the page holds it).
std::string pageWithToken(const std::string& token) {
    std::string page = kViewerPage;
    const std::string placeholder = R"(<meta name="ray-token" content="">)";
    const size_t at = page.find(placeholder);
    if (at != std::string::npos) page.replace(at, placeholder.size(), R"(<meta name="ray-token" content=")" + token + "\">");
    return page;
}

}  // namespace

void defineRoutes(httplib::Server& server, Session& session, const std::string& token) {
    const bool editable = !token.empty();
    server.Get(kPagePath, [page = pageWithToken(token)](const httplib::Request&, httplib::Response& response) {
        response.set_header("Cache-Control", "no-store");
        response.set_header("Content-Security-Policy", kViewerPagePolicy);
        response.set_content(page, "text/html; charset=utf-8");
    });
    server.Get("/settings", [](const httplib::Request&, httplib::Response& response) {
        response.set_content(settingControlsJson().dump(), "application/json");
    });
    server.Get("/fields", [fields = edit::fieldTableJson().dump()](const httplib::Request&, httplib::Response& response) {
        response.set_content(fields, "application/json");
    });
    server.Get("/outline", [&](const httplib::Request&, httplib::Response& response) {
        response.set_content(session.outline().dump(), "application/json");
    });
    server.Get("/node", [&](const httplib::Request& request, httplib::Response& response) {
        answerJson(response, [&] { return session.node(request.get_param_value("id")); });
    });
    server.Get("/state", [&](const httplib::Request&, httplib::Response& response) {
        response.set_content(session.state().dump(), "application/json");
    });
    server.Post("/view", [&](const httplib::Request& request, httplib::Response& response) {
        // The view's number: the page draws over a frame in the camera of the view it shows.
        answerJson(response, [&] { return json{{"view", session.request(request.body)}}; });
    });
    server.Get("/explain", [&](const httplib::Request& request, httplib::Response& response) {
        answerJson(response, [&] { return session.explain(intParameter(request, "x"), intParameter(request, "y")); });
    });
    server.Get("/pick", [&](const httplib::Request& request, httplib::Response& response) {
        answerJson(response, [&] { return session.pick(intParameter(request, "x"), intParameter(request, "y")); });
    });
    server.Get("/object", [&](const httplib::Request& request, httplib::Response& response) {
        answerJson(response, [&] { return session.object(intParameter(request, "id")); });
    });
    // Editing: only with the access token (a viewer started with --no-token shows the scene
    // and does not change it or its file).
    for (const char* action : {"op", "edit", "undo", "redo", "save", "reload"}) {
        server.Post(std::string("/") + action, [&session, action, editable = editable](const httplib::Request& request,
                                                                                     httplib::Response& response) {
            if (!editable) {
                response.status = 403;
                response.set_content(json{{"error", "this viewer was started with --no-token: editing the scene "
                                                    "needs the access token; start ray view without --no-token"}}
                                         .dump(),
                                     "application/json");
                return;
            }
            try {
                response.set_content(session.edit(action, request.body).dump(), "application/json");
            } catch (const FileExists& e) {
                response.status = 409;
                response.set_content(json{{"error", e.what()}, {"exists", true}}.dump(), "application/json");
            } catch (const StaleRevision& e) {
                // With the scene's state, which the page shows before the user acts again.
                response.status = 409;
                response.set_content(json{{"error", e.what()}, {"stale", true}, {"revision", e.current},
                                          {"state", session.state()}}.dump(),
                                     "application/json");
            } catch (const ChangedOnDisk& e) {
                response.status = 409;
                response.set_content(json{{"error", e.what()}, {"changed_on_disk", true}}.dump(), "application/json");
            } catch (const EditError& e) {
                refused(response, e);
            } catch (const json::exception& e) {
                badRequest(response, std::string("the edit is not JSON as expected: ") + e.what());
            } catch (const std::exception& e) {
                badRequest(response, e.what());
            }
        });
    }
    server.Get("/events", [&](const httplib::Request&, httplib::Response& response) {
        response.set_header("Cache-Control", "no-cache");
        auto cursor = std::make_shared<Session::Cursor>();
        cursor->id = session.openStream();
        response.set_chunked_content_provider("text/event-stream", [&session, cursor](size_t, httplib::DataSink& sink) {
            return session.stream(sink, *cursor);
        });
    });
}

void guardRequests(httplib::Server& server, const GuardPolicy& policy) {
    server.set_pre_routing_handler([policy](const httplib::Request& request, httplib::Response& response) {
        return guardRequest(request, response, policy);
    });
    server.set_error_handler(httplib::Server::HandlerWithResponse(explainError));
}

}  // namespace ray
