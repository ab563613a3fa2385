"""parse_request: every field typed and bounded, every refusal a RequestError of one line."""

import pytest

from joshua_codegen.supervisor.control_request import (
    CONTROL_LOG_LINES_DEFAULT,
    CONTROL_LOG_LINES_MAX,
    CONTROL_PATH_MAX,
    CONTROL_REQUEST_DEPTH,
    RequestError,
    nesting_depth,
    parse_request,
)

PATH_RULE = f"path must be an absolute path of at most {CONTROL_PATH_MAX} characters, without NUL"


@pytest.mark.parametrize(
    ("line", "checked"),
    [
        (b'{"command": "status"}', {"command": "status"}),
        (b'{"command": "stop", "node": "arm"}', {"command": "stop", "node": "arm"}),
        (
            b'{"command": "logs", "node": "arm"}',
            {"command": "logs", "node": "arm", "lines": CONTROL_LOG_LINES_DEFAULT, "follow": False, "all": False},
        ),
        (
            b'{"command": "logs", "node": "arm", "lines": 0, "follow": true}',
            {"command": "logs", "node": "arm", "lines": 0, "follow": True, "all": False},
        ),
        (
            b'{"command": "logs", "node": "arm", "all": true}',
            {"command": "logs", "node": "arm", "lines": CONTROL_LOG_LINES_DEFAULT, "follow": False, "all": True},
        ),
        (
            f'{{"command": "logs", "node": "a[{{", "lines": {CONTROL_LOG_LINES_MAX}}}'.encode(),
            {"command": "logs", "node": "a[{", "lines": CONTROL_LOG_LINES_MAX, "follow": False, "all": False},
        ),
        (b'{"command": "reload", "path": "/srv/out2"}', {"command": "reload", "path": "/srv/out2"}),
        (
            f'{{"command": "reload", "path": "/{"a" * (CONTROL_PATH_MAX - 1)}"}}'.encode(),
            {"command": "reload", "path": "/" + "a" * (CONTROL_PATH_MAX - 1)},
        ),
    ],
)
def test_valid_requests_come_out_with_every_field_of_their_command(line, checked):
    assert parse_request(line) == checked


@pytest.mark.parametrize(
    ("line", "error"),
    [
        (b'{"command": "logs", "node": "a", "lines": 1e308}', "lines must be a whole number from 0 to 10000"),
        (b'{"command": "logs", "node": "a", "lines": 10001}', "lines must be a whole number from 0 to 10000"),
        (b'{"command": "logs", "node": "a", "lines": 1E+999}', "not a finite number: 1E+999"),
        (b'{"command": "logs", "node": "a", "lines": -0.0}', "lines must be a whole number from 0 to 10000"),
        (b'{"command": "start", "node": null}', "node must be a string"),
        (b'{"command": "logs", "node": "a", "all": 1}', "all must be true or false"),
        (b'{"command": "start", "node": "a", "node2": "b"}', "unknown field 'node2' for start (it takes node)"),
        (b'{"command": null}', "command must be one of status, restart, stop, start, logs, reload"),
        (b'{"command": "STATUS"}', "unknown command 'STATUS' (status, restart, stop, start, logs, reload)"),
        (b'{"command": "reload"}', "reload needs a path"),
        (b'{"command": "reload", "path": 3}', PATH_RULE),
        (b'{"command": "reload", "path": "out2"}', PATH_RULE),
        (b'{"command": "reload", "path": "/a\\u0000b"}', PATH_RULE),
        (f'{{"command": "reload", "path": "/{"a" * CONTROL_PATH_MAX}"}}'.encode(), PATH_RULE),
        (b'{"command": "reload", "path": "/out2", "node": "a"}', "unknown field 'node' for reload (it takes path)"),
        (b"null", "a request is one JSON object per line, not NoneType"),
        (b"[" * (CONTROL_REQUEST_DEPTH + 1), f"request nested deeper than {CONTROL_REQUEST_DEPTH} levels"),
    ],
)
def test_each_refusal_names_what_is_wrong_in_one_line(line, error):
    with pytest.raises(RequestError) as refused:
        parse_request(line)
    assert str(refused.value) == error


def test_brackets_inside_strings_do_not_count_as_nesting():
    assert nesting_depth('{"a": "[[[[[[\\"[[[[", "b": [{}]}') == 3
