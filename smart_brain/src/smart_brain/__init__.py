"""The Smart layer: strategies, actions and the state machine library that runs them."""
