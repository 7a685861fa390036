"""ray view keeps answering its page while local clients without the token send their requests
slowly (viewer/connection_deadlines.h): 30 connections trickling header lines, one trickling a
body. The page's /state (with the token) answers within a second while they trickle; each
trickling connection is closed by its deadline (headers within 5 s of the request's start, a
body within 10 s), the ones still open then answered 408. Everything on 127.0.0.1; the
trickling loop ends by itself.  Usage: python3 test_slow_clients.py RAY SCENE"""
import select
import socket
import sys
import time

from viewer_harness import Viewer

HEADER_DEADLINE, BODY_DEADLINE = 5, 10  # connection_deadlines.h
SLACK = 3  # seconds a closed connection may take to be noticed on a loaded machine
TRICKLERS = 30

viewer = Viewer(sys.argv[1], sys.argv[2], "--width", "32", "--height", "24")


class Trickler:
    """A connection sending its request a line (or a byte) at a time; notes when the server
    closes it and what it answered."""

    def __init__(self, head, drip):
        self.socket = socket.create_connection(("127.0.0.1", viewer.port), timeout=5)
        self.socket.setblocking(False)
        self.opened = time.time()
        self.closed = None
        self.reply = b""
        self.drip = drip
        self.socket.send(head)

    def step(self):
        """Sends the next drop; reads what came back. False once the server has closed it."""
        if self.closed:
            return False
        try:
            while select.select([self.socket], [], [], 0)[0]:
                data = self.socket.recv(65536)
                if not data:
                    return self._gone()
                self.reply += data
            self.socket.send(self.drip)
        except OSError:  # reset, or a send after the server's close
            return self._gone()
        return True

    def _gone(self):
        self.closed = time.time()
        self.socket.close()
        return False


try:
    viewer.wait_frame_done()
    host = f"Host: 127.0.0.1:{viewer.port}\r\n".encode()
    # No token, headers never finished: a line every 0.3 s keeps each read within any per-read timeout.
    tricklers = [Trickler(b"GET /state HTTP/1.1\r\n" + host, b"X-Trickle: 1\r\n") for _ in range(TRICKLERS)]
    # With the token, a body that never finishes: a byte every 0.3 s.
    body = Trickler(b"POST /view HTTP/1.1\r\n" + host + f"Authorization: token {viewer.token}\r\n".encode() +
                    b"Content-Type: application/json\r\nContent-Length: 100\r\n\r\n{", b" ")
    everyone = tricklers + [body]
    answered = []
    stop = time.time() + BODY_DEADLINE + 2 * SLACK  # the loop's own end, whatever happens
    next_state = time.time() + 1
    while time.time() < stop and any(t.closed is None for t in everyone):
        for t in everyone:
            t.step()
        if time.time() >= next_state and len(answered) < 3:
            # The page asks while they trickle: an answer within 1 s (a timeout raises).
            started = time.time()
            status, state = viewer.json("GET", "/state", timeout=1)
            assert status == 200 and "scene" in state, (status, state)
            answered.append(time.time() - started)
            next_state = time.time() + 1
        time.sleep(0.3)
    assert len(answered) == 3, "the trickling clients outlived the test's loop before /state was asked"
    print(f"/state answered {len(answered)} times while {TRICKLERS} connections trickled headers, "
          f"slowest {max(answered) * 1000:.0f} ms")

    lasted = [t.closed - t.opened if t.closed else None for t in tricklers]
    assert all(d is not None and d <= HEADER_DEADLINE + SLACK for d in lasted), lasted
    late = [t for t in tricklers if t.closed - t.opened >= HEADER_DEADLINE - 0.5]
    assert late, "no trickling connection reached its header deadline (all were closed as the oldest)"
    for t in late:
        assert t.reply.startswith(b"HTTP/1.1 408"), t.reply[:200]
    print(f"header tricklers closed: {TRICKLERS - len(late)} at once (beyond the bound on connections "
          f"without the token), {len(late)} at the {HEADER_DEADLINE} s deadline with 408; longest "
          f"{max(lasted):.1f} s")
    assert body.closed and BODY_DEADLINE - 0.5 <= body.closed - body.opened <= BODY_DEADLINE + SLACK, \
        body.closed and body.closed - body.opened
    assert body.reply.startswith(b"HTTP/1.1 408") and b"did not arrive in time" in body.reply, body.reply[:300]
    print(f"body trickler closed after {body.closed - body.opened:.1f} s with 408")

    status, state = viewer.json("GET", "/state", timeout=5)
    assert status == 200 and viewer.alive()
finally:
    viewer.close()
