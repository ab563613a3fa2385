"""`joshua-fleet deploy OUT` and `joshua-fleet rollback ROBOT`: a fleet's releases rolled out with the
playbooks `joshuac build FLEET -o OUT` wrote (OUT/ansible/), canaries first, then batches.

    inventory.py   the robots and settings of OUT/ansible/inventory.yml
    batches.py     which robots a run takes (--limit) and in what batches (--canary, --batch)
    playbook.py    one ansible-playbook run over some robots, and each robot's outcome
    state.py       the rollout's progress, kept in a file the fleet view reads
    deploy.py      the rollout: batches in turn, the policy when a robot fails, one line per robot
    cli.py         the two commands' options
"""
