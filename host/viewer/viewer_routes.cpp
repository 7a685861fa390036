#include "viewer/viewer_routes.h"

#include <httplib.h>

#include <charconv>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/message_text.h"
#include "edit/edit_json.h"
#include "viewer/connection_deadlines.h"
#include "viewer/folder_files.h"
#include "viewer/request_guard.h"
#include "viewer/viewer_page.h"
#include "viewer/viewer_session.h"

namespace ray {

using nlohmann::json;

namespace {

// Every JSON answer: its text as jsonText writes it (view_request.h: valid UTF-8 whatever
// bytes a path held).
void sendJson(httplib::Response& response, const json& answer) {
    response.set_content(jsonText(answer), "application/json");
}

void badRequest(httplib::Response& response, const std::string& why) {
    response.status = 400;
    sendJson(response, json{{"error", why}});
}

// An edit refused: 400 with the sentence, the field and the node it is about; 409 for a
// name in use (docs/modeler-protocol.md).
void refused(httplib::Response& response, const EditError& error) {
    response.status = error.kind == EditError::Kind::Exists ? 409 : 400;
    sendJson(response, edit::errorJson(error));
}

// Answers with what `answer` returns, as JSON; a refused edit or a bad request (a missing or
// malformed parameter) as 400 with its sentence (refused, badRequest).
template <typename Answer>
void answerJson(httplib::Response& response, Answer&& answer) {
    try {
        sendJson(response, answer());
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

// A body that is not UTF-8 is refused with a sentence of its own (request_guard.h) before a
// parser sees it.
void requireUtf8Body(const httplib::Request& request) {
    if (std::optional<std::string> problem = bodyEncodingProblem(request.body)) throw std::invalid_argument(*problem);
}

// Whether a request comes with a body: the guard runs before cpp-httplib reads it, so its
// headers tell.
bool carriesBody(const httplib::Request& request) {
    const std::string length = request.get_header_value("Content-Length");
    return (!length.empty() && length != "0") || request.has_header("Transfer-Encoding");
}

// Headers every answer carries: it is never framed (but by the pages of --frame-ancestors,
// which the page's Content-Security-Policy names), read by another origin or sniffed.
void setProtectiveHeaders(httplib::Response& response, const GuardPolicy& policy) {
    response.set_header("X-Content-Type-Options", "nosniff");
    if (policy.frameAncestors.empty()) response.set_header("X-Frame-Options", "DENY");
    response.set_header("Cross-Origin-Resource-Policy", "same-origin");
    response.set_header("Referrer-Policy", "no-referrer");
}

// What the guard is shown of a request.
RequestFacts factsOf(const httplib::Request& request) {
    return {request.method,
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
}

// The check every request passes first (viewer/request_guard.h). A first visit to the page
// with the token in its query gets the cookie and is sent on to the bare URL.
httplib::Server::HandlerResponse guardRequest(const httplib::Request& request, httplib::Response& response,
                                              const GuardPolicy& policy) {
    using Result = httplib::Server::HandlerResponse;
    setProtectiveHeaders(response, policy);
    const GuardVerdict verdict = checkRequest(factsOf(request), policy);
    if (verdict.status != 0) {
        response.status = verdict.status;
        sendJson(response, json{{"error", verdict.message}});
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
    if (requestOutOfTime()) {
        response.status = 408;
        why = "the request did not arrive in time (its headers within " + std::to_string(kHeaderDeadline.count()) +
              " s of its start, its body within " + std::to_string(kBodyDeadline.count()) + " s)";
    } else if (response.status == 413)
        why = "the request's body is over the " + std::to_string(kMaxRequestBody / 1024) + " KiB limit";
    else if (response.status == 404)
        why = "there is no such route (the viewer serves /, /state, /settings, /fields, /outline, /node, /events, "
              "/view, /pick, /object, /explain, /op, /edit, /undo, /redo, /save and /recovery)";
    sendJson(response, json{{"error", why}});
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

// The page's Content-Security-Policy, with the pages that may frame it (none by default).
std::string pagePolicy(const std::string& frameAncestors) {
    std::string policy = kViewerPagePolicy;
    const std::string none = "frame-ancestors 'none'";
    const size_t at = policy.find(none);
    if (!frameAncestors.empty() && at != std::string::npos)
        policy.replace(at, none.size(), "frame-ancestors " + frameAncestors);
    return policy;
}

}  // namespace

void defineRoutes(httplib::Server& server, Session& session, const std::string& token,
                  const std::string& frameAncestors) {
    const bool editable = !token.empty();
    server.Get(kPagePath, [page = pageWithToken(token), policy = pagePolicy(frameAncestors)](
                              const httplib::Request&, httplib::Response& response) {
        response.set_header("Cache-Control", "no-store");
        response.set_header("Content-Security-Policy", policy);
        response.set_content(page, "text/html; charset=utf-8");
    });
    server.Get("/settings", [](const httplib::Request&, httplib::Response& response) {
        sendJson(response, settingControlsJson());
    });
    server.Get("/fields", [fields = jsonText(edit::fieldTableJson())](const httplib::Request&, httplib::Response& response) {
        response.set_content(fields, "application/json");
    });
    server.Get("/outline", [&](const httplib::Request&, httplib::Response& response) {
        sendJson(response, session.outline());
    });
    server.Get("/node", [&](const httplib::Request& request, httplib::Response& response) {
        answerJson(response, [&] { return session.node(request.get_param_value("id")); });
    });
    server.Get("/state", [&](const httplib::Request&, httplib::Response& response) {
        sendJson(response, session.state());
    });
    server.Post("/view", [&](const httplib::Request& request, httplib::Response& response) {
        // The view's number: the page draws over a frame in the camera of the view it shows.
        answerJson(response, [&] {
            requireUtf8Body(request);
            return json{{"view", session.request(request.body)}};
        });
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
    // The recovery of unsaved edits another viewer left (viewer/recovery.h): offered to all,
    // restored or discarded (POST /recovery, below) with the token alone.
    server.Get("/recovery", [&](const httplib::Request&, httplib::Response& response) {
        answerJson(response, [&] { return session.recoveryOffer(); });
    });
    // Editing: only with the access token (a viewer started with --no-token shows the scene
    // and does not change it or its file).
    for (const char* action : {"op", "edit", "undo", "redo", "save", "reload", "recovery"}) {
        server.Post(std::string("/") + action, [&session, action, editable = editable](const httplib::Request& request,
                                                                                     httplib::Response& response) {
            if (!editable) {
                response.status = 403;
                sendJson(response, json{{"error", "this viewer was started with --no-token: editing the scene "
                                                  "needs the access token; start ray view without --no-token"}});
                return;
            }
            try {
                requireUtf8Body(request);
                sendJson(response, session.edit(action, request.body));
            } catch (const FileExists& e) {
                response.status = 409;
                sendJson(response, json{{"error", e.what()}, {"exists", true}});
            } catch (const StaleRevision& e) {
                // With the scene's state, which the page shows before the user acts again.
                response.status = 409;
                sendJson(response, json{{"error", e.what()}, {"stale", true}, {"revision", e.current},
                                        {"state", session.state()}});
            } catch (const ChangedOnDisk& e) {
                response.status = 409;
                sendJson(response, json{{"error", e.what()}, {"changed_on_disk", true}});
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

bool passesGuard(const httplib::Request& request, const GuardPolicy& policy) {
    return checkRequest(factsOf(request), policy).status == 0;
}

void guardRequests(httplib::Server& server, const GuardPolicy& policy) {
    server.set_pre_routing_handler([policy](const httplib::Request& request, httplib::Response& response) {
        return guardRequest(request, response, policy);
    });
    server.set_error_handler(httplib::Server::HandlerWithResponse(explainError));
}

}  // namespace ray
