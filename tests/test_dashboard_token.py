"""The dashboard's token file: created private, read back unchanged, refused when someone else could know it."""

import os
import stat

import pytest

from joshua_core.dashboard_token import TokenFileError, load_or_create_token, token_path


def test_the_token_lives_beside_the_control_socket():
    assert str(token_path("/run/user/1000/joshua/arm.sock")) == "/run/user/1000/joshua/arm.dashboard-token"


def test_a_new_token_is_private_and_the_same_at_every_start(tmp_path):
    path = tmp_path / "joshua" / "arm.dashboard-token"
    token = load_or_create_token(path)
    assert len(token) >= 40 and token.isascii()
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    assert stat.S_IMODE(path.parent.stat().st_mode) == 0o700
    assert load_or_create_token(path) == token
    assert sorted(p.name for p in path.parent.iterdir()) == ["arm.dashboard-token"]  # no draft left behind


def test_a_token_written_by_hand_is_used(tmp_path):
    path = tmp_path / "arm.dashboard-token"
    path.write_text("my-own-long-token-1234\n")
    path.chmod(0o600)
    assert load_or_create_token(path) == "my-own-long-token-1234"


@pytest.mark.parametrize(
    "mode, text, message",
    [
        (0o644, "a-token-others-can-read-0123", "that only it may read (it is mode -rw-r--r--"),
        (0o600, "short", "at least 16 characters"),
        (0o600, "has spaces in it, so no", "at least 16 characters"),
    ],
)
def test_an_unsafe_or_unusable_token_file_is_refused_in_one_line(tmp_path, mode, text, message):
    path = tmp_path / "arm.dashboard-token"
    path.write_text(text)
    path.chmod(mode)
    with pytest.raises(TokenFileError) as error:
        load_or_create_token(path)
    assert message in str(error.value) and "\n" not in str(error.value)


def test_a_directory_others_may_write_to_is_refused(tmp_path):
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)
    with pytest.raises(TokenFileError, match="that no one else may write to"):
        load_or_create_token(shared / "arm.dashboard-token")
    assert not (shared / "arm.dashboard-token").exists()


def test_a_file_of_another_user_is_refused(tmp_path):
    path = tmp_path / "arm.dashboard-token"
    path.write_text("planted-by-someone-else-0123")
    path.chmod(0o600)
    os.chown(path, 65534, 65534)
    with pytest.raises(TokenFileError, match="owner 65534"):
        load_or_create_token(path)


def test_a_symbolic_link_is_not_followed(tmp_path):
    target = tmp_path / "elsewhere"
    target.write_text("a-token-somewhere-else-0123")
    target.chmod(0o600)
    (tmp_path / "arm.dashboard-token").symlink_to(target)
    with pytest.raises(TokenFileError, match="cannot read"):
        load_or_create_token(tmp_path / "arm.dashboard-token")
