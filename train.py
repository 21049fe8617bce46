"""Train PPO on the opening task (the design card's entry point; `realikea train` is the same).

python train.py collision=hull resistance=high
python train.py -m collision=coacd,hull resistance=smooth,normal,high
python train.py -m hydra/launcher=joblib collision=coacd,hull   # runs in parallel locally
python train.py -m +experiment=fidelity_ablation   # the ablation (realikea/conf/experiment/)
"""

from realikea.training.main import main

if __name__ == "__main__":
    main()
