"""Shared by E301 and E302: subscriptions whose requested QoS some publisher of the topic does not offer."""

from joshua_codegen.qos_compat import LEVELS
from joshua_codegen.rules.context import Finding, RuleContext


def conflicts(ctx: RuleContext, policy: str, field: str):
    """One finding per subscription that a weaker publisher cannot serve (linear in endpoints)."""
    levels = LEVELS[policy]
    for topic, subscribers in ctx.subscribers.items():
        by_level: dict[int, list] = {}
        for publisher in ctx.publishers.get(topic, ()):
            by_level.setdefault(levels.index(publisher.qos[policy]), []).append(publisher)
        for sub in subscribers:
            wanted = levels.index(sub.qos[policy])
            weaker = [p for level in range(wanted) for p in by_level.get(level, ())]
            if not weaker:
                continue
            first = weaker[0]
            more = f" (and {len(weaker) - 1} more)" if len(weaker) > 1 else ""
            yield Finding(
                ctx.qos_at(sub, field),
                f'publisher "{first.view.name}"{more} offers {first.qos[policy]}, '
                f'subscriber "{sub.view.name}" requires {sub.qos[policy]} on "{topic}"',
                ((ctx.qos_at(first, field), "publisher declared here"),),
            )
