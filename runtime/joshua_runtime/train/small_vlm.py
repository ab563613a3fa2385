"""A small SmolVLM backbone for SmolVLA made on this machine: its configuration, image processor and tokenizer.

LeRobot's SmolVLA builds its vision-language model from a SmolVLM configuration and reads its
processor (tokenizer and image processor) with `AutoProcessor.from_pretrained`, by default from the
Hugging Face Hub (`HuggingFaceTB/SmolVLM2-500M-Video-Instruct`, 500M parameters). `write(directory)`
writes a few-layer one instead, with no download: a byte-level tokenizer (the 256 byte symbols and
SmolVLM's special tokens, no merges: any text encodes, one token per byte), SmolVLM's image and video
processors, and a SmolVLM configuration of SIZES. Its weights start random (SmolVLA's
`load_vlm_weights` stays false) and are saved with the policy.
Importing this module imports transformers.
"""

from pathlib import Path

from transformers import PreTrainedTokenizerFast, SmolVLMConfig, SmolVLMProcessor
from transformers.models.smolvlm import SmolVLMImageProcessor, SmolVLMVideoProcessor

# SmolVLM's special tokens, named as its processor looks them up on the tokenizer.
PAD, BEGIN, END_OF_UTTERANCE = "<pad>", "<|im_start|>", "<end_of_utterance>"
IMAGE_TOKENS = {
    "fake_image_token": "<fake_token_around_image>",
    "global_image_token": "<global-img>",
    "image_token": "<image>",
    "end_of_utterance_token": END_OF_UTTERANCE,
}
# Square images of IMAGE_SIZE pixels in patches of PATCH_SIZE: 16 patches, 4 tokens per image after
# SmolVLM's pixel shuffle (SCALE_FACTOR 2).
IMAGE_SIZE, PATCH_SIZE, SCALE_FACTOR = 64, 16, 2
VISION_SIZES = {"hidden_size": 32, "intermediate_size": 64, "num_hidden_layers": 1, "num_attention_heads": 2}
TEXT_SIZES = {
    "hidden_size": 64,
    "intermediate_size": 128,
    "num_hidden_layers": 2,
    "num_attention_heads": 4,
    "num_key_value_heads": 2,
    "head_dim": 16,
    "max_position_embeddings": 512,
    "rms_norm_eps": 1e-5,
}


def tokenizer() -> PreTrainedTokenizerFast:
    """The byte-level tokenizer: SmolVLM's special tokens first, then the 256 byte symbols."""
    from tokenizers import Tokenizer, decoders, models, pre_tokenizers

    special = [PAD, BEGIN, *dict.fromkeys(IMAGE_TOKENS.values())]
    vocabulary = {token: index for index, token in enumerate(special)}
    for symbol in sorted(pre_tokenizers.ByteLevel.alphabet()):
        vocabulary[symbol] = len(vocabulary)
    model = Tokenizer(models.BPE(vocab=vocabulary, merges=[]))
    model.pre_tokenizer = pre_tokenizers.ByteLevel(add_prefix_space=False)
    model.decoder = decoders.ByteLevel()
    model.add_special_tokens(special)
    return PreTrainedTokenizerFast(
        tokenizer_object=model,
        pad_token=PAD,
        bos_token=BEGIN,
        eos_token=END_OF_UTTERANCE,
        extra_special_tokens=IMAGE_TOKENS,
    )


def write(directory: Path) -> Path:
    """Write the small backbone's configuration and processor into `directory` (created); return it."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    text = tokenizer()
    size = {"longest_edge": IMAGE_SIZE}
    processor = SmolVLMProcessor(
        image_processor=SmolVLMImageProcessor(do_image_splitting=False, size=size, max_image_size=size),
        tokenizer=text,
        video_processor=SmolVLMVideoProcessor(size=size, max_image_size=size),
        image_seq_len=(IMAGE_SIZE // PATCH_SIZE // SCALE_FACTOR) ** 2,
    )
    processor.save_pretrained(directory)
    pad_id = text.convert_tokens_to_ids(PAD)
    SmolVLMConfig(
        image_token_id=text.convert_tokens_to_ids(IMAGE_TOKENS["image_token"]),
        pad_token_id=pad_id,
        scale_factor=SCALE_FACTOR,
        vision_config={**VISION_SIZES, "image_size": IMAGE_SIZE, "patch_size": PATCH_SIZE},
        text_config={"model_type": "llama", "vocab_size": len(text), "pad_token_id": pad_id, **TEXT_SIZES},
    ).save_pretrained(directory)
    return directory
