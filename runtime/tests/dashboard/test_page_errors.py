"""The watch for page errors of browser(): a page error nobody expected fails its block, also when the blocks
share one Chromium (as the tests of a module do), and nothing of one block reaches the next."""

import pytest
from dashboard_support import browser, headless_chromium

pytestmark = pytest.mark.browser

FINE = "data:text/html,<p>fine</p>"
THROWS = "data:text/html,<script>throw new Error('boom')</script>"


def test_a_page_error_fails_its_block_on_a_shared_chromium_and_only_that_block():
    with headless_chromium() as instance:
        with browser(instance) as first:
            first.new_page().goto(FINE)
        with pytest.raises(AssertionError, match="uncaught Error: boom"):
            with browser(instance) as second:
                second.new_page().goto(THROWS)
        with browser(instance) as third:
            third.new_page().goto(FINE)
        assert instance.contexts == []  # each page's own context was closed with its block
