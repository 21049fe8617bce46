"""The generalist screen's candidates (README.md, "One policy on every seed" and its later
rounds): each single-run candidate's overrides and iterations, each distilled candidate's stages
(run by the screen, or by one staged launch), and the rounds that registered them. `screen.py`
trains them.
"""

COMMON = ("logger=none",)
# a candidate's single run, and each run of a candidate the screen drives stage by stage: one
# training run (the library draw's default became a pipeline, round 18's adopted
# distilled_pairs_student_96, after the screen)
ONE_RUN = ("pipeline=none",)
# round 1 ran on python train.py's defaults of its day: the library's draw, CoACD, normal and the
# single-task agent (the library draw's default became agent=multitask, round 1's adopted
# group_ppo, after it); later rounds run on the defaults round 1 left
ROUND_1 = ("agent=ppo",)
AJAR_FP_DOORS = (
    "+task.ajar_share=0.3",
    "+task.ajar_groups=[finger_pull_door]",
    "+task.ajar_range=[0.4,1.0]",
)
SINGLE_RUN = {  # name -> (overrides, iterations)
    "group_ppo": (
        (
            *ROUND_1,
            "+agent.group_advantages=true",
            "agent.algorithm.schedule=fixed",
            "agent.algorithm.learning_rate=3e-4",
            "agent.num_steps_per_env=48",
        ),
        1500,
    ),
    "pregrasp": (
        (
            *ROUND_1,
            "+task.pregrasp_share=0.3",
            "+task.pregrasp_groups=[knob_door,two_point_door,finger_pull_door]",
        ),
        1500,
    ),
    "fp_pregrasp": (
        ("+task.pregrasp_share=0.5", "+task.pregrasp_groups=[finger_pull_door]"),
        1500,
    ),
    # the opening paid up to 1.25 x the success threshold (realikea/rewards/gated.py)
    "open_margin": (("task.reward.open_target=1.25",), 1500),
    # open jaws paid only before the episode's first grasp (realikea/rewards/gated.py)
    "hold_grasp": (("task.reward.reopen_bonus=false",), 1500),
    # every 10 iterations each env takes its group's next configuration
    # (realikea/training/rotating_draw.py): a group trains on all of its configurations
    "rotate": (("asset.rotate_every=10",), 1500),
    # rotate's draw, and 0.3 of the finger-pull door episodes start with the door ajar at 0.4-1.0
    # of the success mark, the hand at home (realikea/tasks/start_state.py)
    "rotate_ajar": (("asset.rotate_every=10", *AJAR_FP_DOORS), 1500),
}
# teachers: fixed poses to 200, then randomized (as the door specialists: 300 of 600); the
# student on randomized poses throughout (its teachers have learned them)
TEACHER_ITERATIONS, TEACHER_SWITCH, STUDENT_ITERATIONS = 400, 200, 200
DISTILLED = {  # name -> (overrides every stage adds, {group: (iterations, fixed poses until)})
    # a group's own teacher from the start, on the candidate's seed (`own`); any other group
    # gets one only by the teacher rule (its kind's teacher below LEARNED), on the next seed
    "distilled": ((), {}),
    # every stage takes turns over its groups' configurations; finger-pull doors' teacher is the
    # specialist `fp_doors_rotate` (train_gated.py) of the README's check before round 7
    "distilled_rotate": (("asset.rotate_every=10",), {"finger_pull_door": (1000, 500)}),
}
STAGED = {  # name -> the overrides of one launch that trains every stage (training/pipeline.py)
    # distilled_rotate's stages, the teachers two at a time with one env worker each
    "distilled_pairs": ("pipeline=distilled_pairs",),
    # and knob doors always given their own teacher (realikea/conf/pipeline/)
    "distilled_pairs_knob": ("pipeline=distilled_pairs_knob",),
    # and a group's own teacher that misses the teacher rule trains again on the next seed
    "distilled_pairs_retry": ("pipeline=distilled_pairs_retry",),
    # and knob doors' own teacher twice as long (800 iterations, poses fixed to 400)
    "distilled_pairs_long_knob": ("pipeline=distilled_pairs_long_knob",),
    # or round 10's with knob doors' own teacher at a fixed rate of 3e-4
    "distilled_pairs_knob_fixed_lr": ("pipeline=distilled_pairs_knob_fixed_lr",),
    # and that round's student distilled twice as long (400 iterations)
    "distilled_pairs_long_student": ("pipeline=distilled_pairs_long_student",),
    # and each group taught by whichever of its teachers ends with the highest success on it
    "distilled_pairs_best_teacher": ("pipeline=distilled_pairs_best_teacher",),
    # or round 13's with knob doors' own teacher started from the door teacher's actor
    "distilled_pairs_knob_from_door": ("pipeline=distilled_pairs_knob_from_door",),
    # and that teacher twice as long (400 iterations), each door group drawn twice as often for
    # the student
    "distilled_pairs_student_doors2": ("pipeline=distilled_pairs_student_doors2",),
    # or that with knob doors' teacher at 200 iterations again and, below 0.9, a second one from
    # scratch, the better teaching
    "distilled_pairs_knob_second_teacher": ("pipeline=distilled_pairs_knob_second_teacher",),
    # and the student's rollout on 96 envs in place of 64
    "distilled_pairs_student_96": ("pipeline=distilled_pairs_student_96",),
    # and every teacher held to 0.9: a group its kind's teacher leaves between 0.5 and 0.9
    # fine-tuned from that teacher, a finger-pull door specialist below 0.9 trained again, each
    # teaching only if better
    "distilled_pairs_fine_tune": ("pipeline=distilled_pairs_fine_tune",),
    # and every rule reading a teacher's success on the validation draw (its mean action, 50
    # episodes a group) in place of its last training window
    "distilled_pairs_validated": ("pipeline=distilled_pairs_validated",),
    # round 19's with the 0.9 marks read there and the teacher rule (0.5) on training success
    "distilled_pairs_validated_marks": ("pipeline=distilled_pairs_validated_marks",),
    # and a teacher-rule teacher below 0.9 there trained again on the seed after its own
    "distilled_pairs_rule_retrain": ("pipeline=distilled_pairs_rule_retrain",),
    # and the student acting on its mean action in its DAgger rollouts
    "distilled_pairs_student_mean": ("pipeline=distilled_pairs_student_mean",),
    # round 22's with the student acting on samples of std 0.3 (in place of 0.1) in its rollouts
    "distilled_pairs_student_noise": ("pipeline=distilled_pairs_student_noise",),
    # and every teacher also read in high resistance there, each rule reading its lower rate
    "distilled_pairs_judged_high": ("pipeline=distilled_pairs_judged_high",),
    # and every two-point teacher also read on each family's smallest train part (a door on each
    # hinge side apart), a fine-tune that misses followed by a teacher of the group's own
    "distilled_pairs_small_parts": ("pipeline=distilled_pairs_small_parts",),
    # and the student read there too once its 400 iterations are done, then trained 200 more with
    # each group it reads below 0.9 given twice its turns of the draw
    "distilled_pairs_student_small_parts": ("pipeline=distilled_pairs_student_small_parts",),
    # and the student seeing and driving each door whose arm starts mirrored as its hinge twin
    "distilled_pairs_student_mirrored": ("pipeline=distilled_pairs_student_mirrored",),
}
ROUNDS = {
    1: ("group_ppo", "pregrasp", "distilled"),
    2: ("fp_pregrasp",),
    3: ("open_margin",),
    4: ("hold_grasp",),
    5: ("rotate",),
    6: ("rotate_ajar",),
    7: ("distilled_rotate",),
    8: ("distilled_pairs",),
    9: ("distilled_pairs_knob",),
    10: ("distilled_pairs_retry",),
    11: ("distilled_pairs_long_knob",),
    12: ("distilled_pairs_knob_fixed_lr",),
    13: ("distilled_pairs_long_student",),
    14: ("distilled_pairs_best_teacher",),
    15: ("distilled_pairs_knob_from_door",),
    16: ("distilled_pairs_student_doors2",),
    17: ("distilled_pairs_knob_second_teacher",),
    18: ("distilled_pairs_student_96",),
    19: ("distilled_pairs_fine_tune",),
    20: ("distilled_pairs_validated",),
    21: ("distilled_pairs_validated_marks",),
    22: ("distilled_pairs_rule_retrain",),
    23: ("distilled_pairs_student_mean",),
    24: ("distilled_pairs_student_noise",),
    25: ("distilled_pairs_judged_high",),
    26: ("distilled_pairs_small_parts",),
    27: ("distilled_pairs_student_small_parts",),
    28: ("distilled_pairs_student_mirrored",),
}
CANDIDATES = tuple(c for candidates in ROUNDS.values() for c in candidates)
