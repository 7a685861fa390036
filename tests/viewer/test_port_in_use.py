"""Two viewers on one port: the second is refused with a clear message and exit 3, and the
first keeps serving alone (cpp-httplib's SO_REUSEPORT once let both listen and share the
requests). Usage: python3 test_port_in_use.py RAY_BINARY SCENE"""
import subprocess
import sys

from viewer_harness import Viewer

ray, scene = sys.argv[1], sys.argv[2]
first = Viewer(ray, scene, "--width", "16", "--height", "12")
try:
    first.wait_frame_done()
    second = subprocess.run([ray, "view", scene, "--port", str(first.port), "--width", "16", "--height", "12"],
                            capture_output=True, text=True, timeout=60)
    message = second.stdout + second.stderr
    print(f"second viewer on port {first.port}: exit {second.returncode}: {message.strip()}")
    assert second.returncode == 3, second.returncode
    assert f"port {first.port} on 127.0.0.1 is already in use" in message and "--port" in message, message
    assert "http://" not in message, "the second viewer printed a URL"
    for _ in range(20):  # every request reaches the first viewer, whose scene answers
        status, state = first.json("GET", "/state")
        assert status == 200 and state["width"] == 16, (status, state)
    assert first.alive()
finally:
    first.close()
print("port in use: refused")
