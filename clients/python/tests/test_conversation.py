"""A dialogue in the human's words against the live service: a question, its answer, pronouns
that carry over, answers the robot could not place, and taking a question back."""

from __future__ import annotations

from scruple_client import Client, Conversation, NormDto, objects_in

from scenes import KITCHEN, LAB, VASE_ASSUMED, WHICH_MUG


def test_ask_then_answer_in_words_then_comply(client: Client, paper_norms: list[NormDto]) -> None:
    conv = Conversation(client, KITCHEN)

    asked = conv.say("Get the mug.")
    assert asked.decision == "ask"
    assert asked.utterance == WHICH_MUG
    assert asked.offered == ["did(self,get(mug2))", "did(self,get(mug1))"]
    assert conv.awaiting_answer and conv.question == WHICH_MUG

    done = conv.say("the red one")
    assert (done.decision, done.utterance, done.goal) == ("comply", "Okay.", "did(self,get(mug1))")
    # The answer went with the request that asked, as the contract's follow-up does.
    sent = conv.last_request
    assert sent is not None and sent.answer is not None
    assert sent.answer.text == "the red one"
    assert sent.directive.text == "Get the mug."
    assert not conv.awaiting_answer and conv.question is None
    assert conv.focus == ["mug1"]

    # The exchange is over: the next words are a new directive, and "it" is the red mug.
    moved = conv.say("Put it in the sink.")
    assert (moved.decision, moved.goal) == ("comply", "did(self,put(mug1,sink1))")
    assert conv.last_request is not None
    assert conv.last_request.answer is None
    assert conv.last_request.directive.text == "Put it in the sink."
    assert conv.last_request.focus == ["mug1"]
    assert conv.focus == ["mug1", "sink1"]

    refused = conv.say("Smash it.")
    assert refused.decision == "refuse"
    assert refused.utterance == "I cannot destroy the red mug because destroy is forbidden action."


def test_the_second_one_counts_the_question_s_readings(client: Client, paper_norms: list[NormDto]) -> None:
    conv = Conversation(client, KITCHEN)
    assert conv.say("Get the mug.").decision == "ask"
    chosen = conv.say("the second one")
    assert (chosen.decision, chosen.goal) == ("comply", "did(self,get(mug1))")


def test_an_answer_the_robot_cannot_place_leaves_the_question_open(client: Client, paper_norms: list[NormDto]) -> None:
    conv = Conversation(client, KITCHEN)
    conv.say("Get the mug.")
    unplaced = conv.say("the green one")
    assert unplaced.decision == "unresolved"
    assert unplaced.utterance == "I do not know what you mean by the green one."
    assert conv.awaiting_answer and conv.question == WHICH_MUG
    assert (conv.say("the blue one").goal) == "did(self,get(mug2))"


def test_never_mind_takes_the_question_back(client: Client, paper_norms: list[NormDto]) -> None:
    conv = Conversation(client, KITCHEN)
    conv.say("Get the mug.")
    cancelled = conv.say("never mind")
    assert (cancelled.decision, cancelled.utterance, cancelled.goal) == ("cancelled", "Okay, I will not.", None)
    assert not conv.awaiting_answer
    # A new directive, not an answer to a question no longer asked.
    again = conv.say("Get the mug.")
    assert again.decision == "ask" and conv.last_request is not None and conv.last_request.answer is None


def test_a_whole_directive_as_the_answer_is_decided_as_one(client: Client, paper_norms: list[NormDto]) -> None:
    conv = Conversation(client, LAB)
    assert conv.say("Get the notebook.").decision == "ask"
    instead = conv.say("Get the vase.")
    assert (instead.decision, instead.utterance) == ("assume", VASE_ASSUMED)
    assert not conv.awaiting_answer
    assert conv.focus == ["object4"]


def test_a_new_question_from_an_answer_is_answered_against_its_own_directive(
    client: Client, paper_norms: list[NormDto]
) -> None:
    conv = Conversation(client, LAB)
    assert conv.say("Get the vase.").decision == "assume"
    assert conv.say("Point to the notebook.").decision == "ask"
    # The answer is a whole directive that asks a question of its own ...
    asked = conv.say("Get the notebook.")
    assert asked.decision == "ask"
    assert asked.offered == ["did(self,get(object2))", "did(self,get(object1))"]
    # ... so the next answer picks among the notebooks to get, not to point to.
    picked = conv.say("the red one")
    assert (picked.decision, picked.goal) == ("comply", "did(self,get(object1))")


def test_confirm_then_yes(client: Client, paper_norms: list[NormDto]) -> None:
    conv = Conversation(client, LAB, options={"single_permissible": "confirm"})
    assert conv.say("Get the vase.").decision == "confirm"
    agreed = conv.say("yes")
    assert (agreed.decision, agreed.goal) == ("comply", "did(self,get(object4))")


def test_a_refusal_puts_its_object_in_focus(client: Client, paper_norms: list[NormDto]) -> None:
    conv = Conversation(client, LAB)
    refused = conv.say("Destroy the plastic vase.")
    assert refused.decision == "refuse"
    assert conv.focus == ["object4"]
    assert conv.say("Point to it.").goal == "did(self,pointTo(object4))"


def test_objects_in_a_term_are_named_in_order() -> None:
    assert objects_in("did(self,and(get(mug2),put(mug2,sink1)))", ["mug1", "mug2", "sink1"]) == ["mug2", "sink1"]
    assert objects_in("did(self,give(knife1,human))", ["knife1"]) == ["knife1"]
